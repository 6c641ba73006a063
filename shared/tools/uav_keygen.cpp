// uav-keygen: writes a new random 32-byte signing key (mode 0600) for uav-onboard --key and
// uav-gcs --key. Copy the same file to the vehicle and to each GCS allowed to command it.
#include <iostream>

#include <CLI/CLI.hpp>

#include "uav/shared/signing.hpp"
#include "uav/shared/decimal.hpp"
#include "uav/shared/program.hpp"

int main(int argc, char** argv) {
  CLI::App cli{"uav-keygen: a new message-signing key shared by a vehicle and its ground stations"};
  std::string path;
  cli.add_option("FILE", path, "key file to create (refuses to overwrite one)")->required();
  uav::PrepareCommandLine(cli);
  CLI11_PARSE(cli, argc, argv);
  try {
    const uav::SigningKey key = uav::SigningKey::Generate(path);
    std::cout << "uav-keygen: wrote " << path << " (32 bytes, mode 0600), key id " << key.Id() << "\n";
    return 0;
  } catch (const std::exception& e) {
    std::cerr << "uav-keygen: " << e.what() << "\n";
    return 1;
  }
}

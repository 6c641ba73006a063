// uav-keygen: writes a new 32-byte signing key (mode 0600) for uav-onboard --key and uav-gcs
// --key: random, or the SHA-256 of a passphrase, the key QGroundControl and Mission Planner
// derive from the passphrase an operator types for MAVLink signing. Copy the same file to the
// vehicle and to each GCS allowed to command it.
#include <iostream>

#include <CLI/CLI.hpp>

#include "uav/shared/signing.hpp"
#include "uav/shared/decimal.hpp"
#include "uav/shared/program.hpp"

int main(int argc, char** argv) {
  CLI::App cli{"uav-keygen: a new message-signing key shared by a vehicle and its ground stations"};
  std::string path, passphrase;
  cli.add_option("FILE", path, "key file to create (refuses to overwrite one)")->required();
  cli.add_option("--passphrase", passphrase,
                 "derive the key from this passphrase (SHA-256, as QGroundControl and Mission Planner do) "
                 "instead of drawing it at random; type the same passphrase into the MAVLink GCS");
  uav::PrepareCommandLine(cli);
  CLI11_PARSE(cli, argc, argv);
  try {
    const uav::SigningKey key =
        passphrase.empty() ? uav::SigningKey::Generate(path) : uav::SigningKey::FromPassphrase(passphrase);
    if (!passphrase.empty()) key.Save(path);
    std::cout << "uav-keygen: wrote " << path << " (32 bytes, mode 0600" << (passphrase.empty() ? "" : ", from the passphrase")
              << "), key id " << key.Id() << "\n";
    return 0;
  } catch (const std::exception& e) {
    std::cerr << "uav-keygen: " << e.what() << "\n";
    return 1;
  }
}

#include "uav/shared/mavlink_transport.hpp"

#include <arpa/inet.h>
#include <fcntl.h>
#include <netdb.h>
#include <sys/socket.h>
#include <termios.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <map>
#include <optional>
#include <stdexcept>

namespace uav::mavlink {
namespace {

int ParsePort(const std::string& text, const std::string& spec) {
  try {
    std::size_t used = 0;
    const int port = std::stoi(text, &used);
    if (used == text.size() && port > 0 && port < 65536) return port;
  } catch (const std::exception&) {
  }
  throw std::invalid_argument("MAVLink endpoint '" + spec + "': port '" + text + "' is not 1..65535");
}

sockaddr_in Resolve(const std::string& host, int port, const std::string& spec) {
  addrinfo hints{};
  hints.ai_family = AF_INET;
  hints.ai_socktype = SOCK_DGRAM;
  addrinfo* found = nullptr;
  if (::getaddrinfo(host.c_str(), nullptr, &hints, &found) != 0 || !found)
    throw std::invalid_argument("MAVLink endpoint '" + spec + "': cannot resolve host '" + host + "'");
  sockaddr_in a = *reinterpret_cast<sockaddr_in*>(found->ai_addr);
  ::freeaddrinfo(found);
  a.sin_port = htons(static_cast<uint16_t>(port));
  return a;
}

class UdpTransport : public MavlinkTransport {
 public:
  // `remote` set: send there; unset: listen on `local` and answer the latest sender.
  UdpTransport(const std::string& spec, const sockaddr_in& local, const std::optional<sockaddr_in>& remote)
      : spec_(spec), remote_(remote) {
    fd_ = ::socket(AF_INET, SOCK_DGRAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
    if (fd_ < 0) throw std::runtime_error("MAVLink endpoint '" + spec + "': socket: " + std::strerror(errno));
    const int one = 1;
    ::setsockopt(fd_, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one);
    if (::bind(fd_, reinterpret_cast<const sockaddr*>(&local), sizeof local) != 0) {
      const std::string why = std::strerror(errno);
      ::close(fd_);
      throw std::runtime_error("MAVLink endpoint '" + spec + "': cannot bind port " +
                               std::to_string(ntohs(local.sin_port)) + ": " + why);
    }
  }
  ~UdpTransport() override { ::close(fd_); }
  std::vector<std::vector<uint8_t>> Receive() override {
    std::vector<std::vector<uint8_t>> out;
    uint8_t buf[65536];
    for (;;) {
      sockaddr_in from{};
      socklen_t len = sizeof from;
      const ssize_t n = ::recvfrom(fd_, buf, sizeof buf, 0, reinterpret_cast<sockaddr*>(&from), &len);
      if (n < 0) break;
      out.emplace_back(buf, buf + n);
      if (listening_) remote_ = from;
    }
    return out;
  }
  bool datagrams() const override { return true; }
  bool Send(const std::vector<uint8_t>& bytes) override {
    if (!remote_) return false;
    return ::sendto(fd_, bytes.data(), bytes.size(), 0, reinterpret_cast<const sockaddr*>(&*remote_), sizeof *remote_) ==
           static_cast<ssize_t>(bytes.size());
  }
  std::string Describe() const override { return spec_; }
  bool listening_ = false;

 private:
  std::string spec_;
  int fd_ = -1;
  std::optional<sockaddr_in> remote_;
};

class SerialTransport : public MavlinkTransport {
 public:
  SerialTransport(const std::string& spec, const std::string& device, int baud) : spec_(spec), baud_(baud) {
    static const std::map<int, speed_t> kBauds = {{9600, B9600},     {19200, B19200},   {38400, B38400},
                                                  {57600, B57600},   {115200, B115200}, {230400, B230400},
                                                  {460800, B460800}, {921600, B921600}};
    const auto b = kBauds.find(baud);
    if (b == kBauds.end())
      throw std::invalid_argument("MAVLink endpoint '" + spec + "': baud rate " + std::to_string(baud) +
                                  " is not one of 9600 19200 38400 57600 115200 230400 460800 921600");
    fd_ = ::open(device.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
    if (fd_ < 0) throw std::runtime_error("MAVLink endpoint '" + spec + "': cannot open " + device + ": " + std::strerror(errno));
    termios t{};
    if (::tcgetattr(fd_, &t) != 0) {
      ::close(fd_);
      throw std::runtime_error("MAVLink endpoint '" + spec + "': " + device + " is not a serial device");
    }
    ::cfmakeraw(&t);
    t.c_cflag |= CLOCAL | CREAD;
    t.c_cflag &= ~CRTSCTS;
    ::cfsetispeed(&t, b->second);
    ::cfsetospeed(&t, b->second);
    ::tcsetattr(fd_, TCSANOW, &t);
  }
  ~SerialTransport() override { ::close(fd_); }
  std::vector<std::vector<uint8_t>> Receive() override {
    std::vector<uint8_t> bytes;
    uint8_t buf[4096];
    ssize_t n;
    while ((n = ::read(fd_, buf, sizeof buf)) > 0) bytes.insert(bytes.end(), buf, buf + n);
    if (bytes.empty()) return {};
    return {std::move(bytes)};
  }
  bool datagrams() const override { return false; }
  bool Send(const std::vector<uint8_t>& bytes) override {
    return ::write(fd_, bytes.data(), bytes.size()) == static_cast<ssize_t>(bytes.size());
  }
  std::string Describe() const override { return spec_; }
  int bytes_per_second() const override { return baud_ / 10; }  // 8N1: ten bits a byte

 private:
  std::string spec_;
  int baud_;
  int fd_ = -1;
};

}  // namespace

std::unique_ptr<MavlinkTransport> OpenMavlinkTransport(const std::string& spec) {
  const std::size_t colon = spec.find(':');
  const std::string kind = spec.substr(0, colon);
  const std::string rest = colon == std::string::npos ? "" : spec.substr(colon + 1);
  const std::size_t last = rest.rfind(':');
  if (kind == "udp") {
    if (last == std::string::npos)
      throw std::invalid_argument("MAVLink endpoint '" + spec + "': udp needs HOST:PORT (udp:127.0.0.1:14550)");
    sockaddr_in local{};
    local.sin_family = AF_INET;
    local.sin_addr.s_addr = htonl(INADDR_ANY);
    return std::make_unique<UdpTransport>(spec, local, Resolve(rest.substr(0, last), ParsePort(rest.substr(last + 1), spec), spec));
  }
  if (kind == "udpin") {
    const std::string host = last == std::string::npos ? "0.0.0.0" : rest.substr(0, last);
    const int port = ParsePort(last == std::string::npos ? rest : rest.substr(last + 1), spec);
    auto t = std::make_unique<UdpTransport>(spec, Resolve(host, port, spec), std::nullopt);
    t->listening_ = true;
    return t;
  }
  if (kind == "serial") {
    if (rest.empty()) throw std::invalid_argument("MAVLink endpoint '" + spec + "': serial needs a device (serial:/dev/ttyUSB0:57600)");
    int baud = 57600;
    std::string device = rest;
    if (last != std::string::npos) {
      device = rest.substr(0, last);
      try {
        baud = std::stoi(rest.substr(last + 1));
      } catch (const std::exception&) {
        throw std::invalid_argument("MAVLink endpoint '" + spec + "': baud rate '" + rest.substr(last + 1) + "' is not a number");
      }
    }
    return std::make_unique<SerialTransport>(spec, device, baud);
  }
  throw std::invalid_argument("MAVLink endpoint '" + spec + "': expected udp:HOST:PORT, udpin:[HOST:]PORT or serial:DEVICE[:BAUD]");
}

}  // namespace uav::mavlink

#pragma once
// A ROS 1 master of one test's own (rosmaster --core, RFIDRAY_ROSMASTER) on loopback, so ROS tests run beside
// anything else on the machine: ROS_MASTER_URI, ROS_IP and ROS_HOME (logs in its scratch directory) are set for
// this process and the children it starts; the master is stopped (SIGTERM, it cleans up on it) and the
// directory removed at the end.
#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <string>
#include <thread>

#include "tests/support/child_process.h"
#include "tests/support/scratch_dir.h"

namespace rfidray::testing {

// True when something accepts TCP connections on 127.0.0.1:port.
inline bool port_open(int port) {
  const int fd = socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_port = htons(static_cast<uint16_t>(port));
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  const bool ok = connect(fd, reinterpret_cast<sockaddr*>(&a), sizeof a) == 0;
  close(fd);
  return ok;
}

inline bool have_rosmaster() {
  const std::string m = RFIDRAY_ROSMASTER;
  return !m.empty() && m.find("NOTFOUND") == std::string::npos;
}

// Helper processes of ROS tests stop on SIGTERM (rosmaster and the listeners clean up on it).
struct RosChild : ChildProcess {
  RosChild(std::vector<std::string> argv, const std::filesystem::path& log)
      : ChildProcess(std::move(argv), log, SIGTERM) {}
};

class RosMaster {
 public:
  // `port`: 20000 + something from the pid (clear of 11311; tests running at once pick different ones).
  RosMaster(const std::string& name, int port) : scratch_(name), dir(scratch_.path()), port_(port) {
    const std::string uri = "http://127.0.0.1:" + std::to_string(port);
    ::setenv("ROS_MASTER_URI", uri.c_str(), 1);
    ::setenv("ROS_IP", "127.0.0.1", 1);
    ::setenv("ROS_HOME", dir.c_str(), 1);
    master_ = std::make_unique<RosChild>(std::vector<std::string>{RFIDRAY_ROSMASTER, "--core", "-p", std::to_string(port)},
                                         dir / "rosmaster.log");
    const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(15);
    while (!up() && std::chrono::steady_clock::now() < until) std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  bool up() const { return port_open(port_); }
  int port() const { return port_; }

 private:
  ScratchDir scratch_;  // declared first: removed after the master has stopped

 public:
  const std::filesystem::path dir;

 private:
  int port_;
  std::unique_ptr<RosChild> master_;
};

}  // namespace rfidray::testing

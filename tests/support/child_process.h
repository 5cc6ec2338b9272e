#pragma once
// A helper process of a test (a listener, a fake simulator, the rfidray binary under test): started with
// posix_spawn, stdout and stderr to a log file, signalled (kill_signal) and reaped at the end if it is still
// running, so an assertion that fails half-way leaves no process behind.
#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <string>
#include <thread>
#include <vector>

extern char** environ;

namespace rfidray::testing {

class ChildProcess {
 public:
  ChildProcess(std::vector<std::string> argv, const std::filesystem::path& log, int kill_signal = SIGKILL)
      : kill_signal_(kill_signal) {
    std::vector<char*> cargv;
    for (auto& a : argv) cargv.push_back(a.data());
    cargv.push_back(nullptr);
    posix_spawn_file_actions_t fa;
    posix_spawn_file_actions_init(&fa);
    posix_spawn_file_actions_addopen(&fa, 1, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_adddup2(&fa, 1, 2);
    if (posix_spawn(&pid_, cargv[0], &fa, nullptr, cargv.data(), environ) != 0) pid_ = -1;
    posix_spawn_file_actions_destroy(&fa);
  }
  ChildProcess(const ChildProcess&) = delete;
  ChildProcess& operator=(const ChildProcess&) = delete;
  ~ChildProcess() {
    if (pid_ > 0 && !done_) {
      kill(pid_, kill_signal_);
      waitpid(pid_, nullptr, 0);
    }
  }
  bool started() const { return pid_ > 0; }
  bool running() const { return pid_ > 0 && !done_; }
  // Exit status, or −1 if it did not exit within the timeout (it is then signalled at destruction).
  int wait(std::chrono::milliseconds timeout) {
    const auto until = std::chrono::steady_clock::now() + timeout;
    while (std::chrono::steady_clock::now() < until) {
      int st = 0;
      if (waitpid(pid_, &st, WNOHANG) == pid_) {
        done_ = true;
        return WIFEXITED(st) ? WEXITSTATUS(st) : -1;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    return -1;
  }

 private:
  int kill_signal_;
  pid_t pid_ = -1;
  bool done_ = false;
};

// `rfidray ARGS...` (the binary under test, RFIDRAY_BINARY), killed (SIGKILL) at the end if still running.
class RfidrayProcess : public ChildProcess {
 public:
  RfidrayProcess(const std::vector<std::string>& args, const std::filesystem::path& log)
      : ChildProcess(with_binary(args), log) {}

 private:
  static std::vector<std::string> with_binary(const std::vector<std::string>& args) {
    std::vector<std::string> argv{RFIDRAY_BINARY};
    argv.insert(argv.end(), args.begin(), args.end());
    return argv;
  }
};

}  // namespace rfidray::testing

#include "io/atomic_file.h"

#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>
#include <fstream>

#include "core/error.h"

namespace rfidray::io {
namespace {

// The temporary being written, for remove_partial_output (a signal handler may read it at any time).
char g_partial[4096];
std::atomic<bool> g_partial_set{false};

void set_partial(const std::string& path) {
  g_partial_set.store(false);
  if (path.size() + 1 > sizeof g_partial) return;
  std::memcpy(g_partial, path.c_str(), path.size() + 1);
  g_partial_set.store(true);
}

}  // namespace

void check_output_path(const std::filesystem::path& path, const std::string& what) {
  std::error_code ec;
  const auto st = std::filesystem::status(path, ec);
  if (!ec && std::filesystem::exists(st) && !std::filesystem::is_regular_file(st))
    throw InputError(path.string() + ": refusing to write " + what + ": it exists and is not a regular file");
}

void write_file_atomic(const std::filesystem::path& path, const std::function<void(std::ostream&)>& body,
                       const std::string& what) {
  check_output_path(path, what);
  const std::filesystem::path tmp = path.string() + ".tmp-" + std::to_string(::getpid());
  auto fail = [&](const std::string& why) {
    g_partial_set.store(false);
    std::error_code ec;
    std::filesystem::remove(tmp, ec);
    return InputError(path.string() + ": cannot write " + what + " (" + why + ")");
  };
  std::ofstream out;
  set_partial(tmp.string());
  out.open(tmp, std::ios::binary | std::ios::trunc);
  if (!out) throw fail(std::strerror(errno));
  try {
    body(out);
  } catch (...) {
    out.close();
    g_partial_set.store(false);
    std::error_code ec;
    std::filesystem::remove(tmp, ec);
    throw;
  }
  out.flush();
  const int flush_errno = errno;
  const bool written = static_cast<bool>(out);
  out.close();
  if (!written || !out) throw fail(std::string("write failed: ") + std::strerror(flush_errno ? flush_errno : EIO));
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) throw fail("rename from " + tmp.filename().string() + ": " + ec.message());
  g_partial_set.store(false);
}

void remove_partial_output() noexcept {
  if (g_partial_set.load()) ::unlink(g_partial);
}

}  // namespace rfidray::io

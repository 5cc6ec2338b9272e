#pragma once
// Output files that appear complete or not at all. Every file rfidray writes (readings CSV, ground truth,
// gen-warehouse OBJ/MTL, compare.csv) goes through write_file_atomic: the body writes a temporary in the same
// directory ("<name>.tmp-<pid>"), which is flushed, closed and then renamed over the final name. A write
// error (disk full, file-size limit), an exception from the body or a signal (see remove_partial_output)
// removes the temporary, so a truncated file never sits under the final name.
#include <filesystem>
#include <functional>
#include <ostream>
#include <string>

namespace rfidray::io {

// Throws InputError "PATH: refusing to write WHAT: not a regular file" when PATH exists and is a device,
// directory, FIFO or socket (e.g. -o /dev/null would otherwise create /dev/null.mtl beside it).
void check_output_path(const std::filesystem::path& path, const std::string& what);

// Writes `path` through `body` atomically (see above). Throws InputError naming the path on open, write or
// rename failure; an exception from `body` propagates after the temporary is removed.
void write_file_atomic(const std::filesystem::path& path, const std::function<void(std::ostream&)>& body,
                       const std::string& what = "output file");

// Async-signal-safe: removes the temporary of the write in progress (if any). For SIGINT/SIGTERM handlers.
void remove_partial_output() noexcept;

}  // namespace rfidray::io

// Whole-file reading and atomic writing, shared by the mesh I/O and the CLI.
#pragma once

#include <functional>
#include <string>
#include <string_view>

namespace foldfill {

// The bytes of `path`. Throws CannotReadError("PATH: reason").
std::string read_file(const std::string& path);

// Writes `bytes` to a temporary file beside `path`, then renames it into place:
// `path` is either left untouched or fully written, with the mode of a new
// file (0666 less the umask). The temporary file has no name while it is
// written (Linux's O_TMPFILE), so that even a killed process leaves nothing
// behind; where the file system has no such files, it is `.foldfill-XXXXXX`
// in the same folder. Throws CannotWriteError("PATH: reason") and removes
// the temporary file on failure.
void write_file_atomically(const std::string& path, std::string_view bytes);

// Receives a file's bytes piece by piece.
using ByteConsumer = std::function<void(std::string_view)>;

// The same for a file produced in pieces: `produce` hands them, in order, to
// the consumer it is given, so that a large file is never whole in memory. An
// exception from `produce` removes the temporary file and propagates.
void write_file_atomically(const std::string& path,
                           const std::function<void(const ByteConsumer&)>& produce);

// Removes the named temporary files of the writes in progress (at most 64 at
// a time are known), for a handler of SIGINT or SIGTERM that ends the process:
// async-signal-safe. Unnamed temporary files need no removal.
void unlink_pending_temporaries() noexcept;

}  // namespace foldfill

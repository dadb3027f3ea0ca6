// Whole-file reading and atomic writing, shared by the mesh I/O and the CLI.
#pragma once

#include <functional>
#include <string>
#include <string_view>

namespace foldfill {

// The bytes of `path`. Throws Error(CannotRead, "PATH: reason").
std::string read_file(const std::string& path);

// Writes `bytes` to a temporary file beside `path`, then renames it into place:
// `path` is either left untouched or fully written. Throws
// Error(CannotWrite, "PATH: reason") and removes the temporary file on failure.
void write_file_atomically(const std::string& path, std::string_view bytes);

// Receives a file's bytes piece by piece.
using ByteConsumer = std::function<void(std::string_view)>;

// The same for a file produced in pieces: `produce` hands them, in order, to
// the consumer it is given, so that a large file is never whole in memory. An
// exception from `produce` removes the temporary file and propagates.
void write_file_atomically(const std::string& path,
                           const std::function<void(const ByteConsumer&)>& produce);

}  // namespace foldfill

// Whole-file reading and atomic writing, shared by the mesh I/O and the CLI.
#pragma once

#include <string>
#include <string_view>

namespace foldfill {

// The bytes of `path`. Throws Error(CannotRead, "PATH: reason").
std::string read_file(const std::string& path);

// Writes `bytes` to a temporary file beside `path`, then renames it into place:
// `path` is either left untouched or fully written. Throws
// Error(CannotWrite, "PATH: reason") and removes the temporary file on failure.
void write_file_atomically(const std::string& path, std::string_view bytes);

}  // namespace foldfill

// Whole-file reading and atomic writing.
#include "foldfill/file.h"

#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "foldfill/error.h"

namespace foldfill {

std::string read_file(const std::string& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) {
    throw Error(ErrorKind::CannotRead, path + ": is a directory, not a mesh file");
  }
  std::ifstream in(path, std::ios::binary);
  if (!in)
    throw Error(ErrorKind::CannotRead, path + ": cannot open (" + std::strerror(errno) + ")");
  std::string bytes;
  in.seekg(0, std::ios::end);
  const std::streamoff size = in.tellg();
  if (size > 0) {
    bytes.resize(static_cast<size_t>(size));
    in.seekg(0);
    in.read(bytes.data(), size);
  }
  if (!in) throw Error(ErrorKind::CannotRead, path + ": read failed");
  return bytes;
}

void write_file_atomically(const std::string& path, std::string_view bytes) {
  write_file_atomically(path, [bytes](const ByteConsumer& write) { write(bytes); });
}

void write_file_atomically(const std::string& path,
                           const std::function<void(const ByteConsumer&)>& produce) {
  const std::string temporary = path + ".tmp-" + std::to_string(::getpid());
  bool written = false;
  {
    std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
    if (out) {
      try {
        produce([&out](std::string_view piece) {
          out.write(piece.data(), static_cast<std::streamsize>(piece.size()));
        });
      } catch (...) {
        out.close();
        std::remove(temporary.c_str());
        throw;
      }
      out.close();  // a late error (disk full) shows up here, before the rename
      written = !out.fail();
    }
  }
  if (!written || std::rename(temporary.c_str(), path.c_str()) != 0) {
    const std::string reason = std::strerror(errno);
    std::remove(temporary.c_str());
    throw Error(ErrorKind::CannotWrite, path + ": cannot write (" + reason + ")");
  }
}

}  // namespace foldfill

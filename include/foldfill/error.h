// The typed errors of foldfill and the process exit codes they map to.
#pragma once

#include <stdexcept>
#include <string>

namespace foldfill {

// Each kind of failure has its own exit code (documented in the README).
enum class ErrorKind {
  Usage = 2,                // bad command line or options file
  CannotRead = 3,           // missing or unreadable input file
  BadFormat = 4,            // empty, garbage, truncated or unsupported file content
  NonFiniteCoordinate = 5,  // NaN or infinite vertex coordinate
  BadFace = 6,              // index out of range, fewer than 3 or repeated vertices
  NonManifold = 7,          // an edge with more than two faces, or a pinched vertex
  NotADisk = 8,             // a selected hole loop that is not a disk boundary
  FillFailed = 9,           // a stage of the fill could not produce a valid patch
  CannotWrite = 10,         // output could not be written
  Internal = 1,             // a bug: should never happen
};

// An error with its kind. `what()` is one line: "FILE: problem" when a file is
// concerned, so the CLI can print it as is.
class Error : public std::runtime_error {
 public:
  Error(ErrorKind kind, const std::string& message) : std::runtime_error(message), kind_(kind) {}
  ErrorKind kind() const { return kind_; }
  int exit_code() const { return static_cast<int>(kind_); }

 private:
  ErrorKind kind_;
};

}  // namespace foldfill

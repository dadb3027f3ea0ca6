// The errors of foldfill: one exception type, Error, whose kind says the
// category of the failure. What a program does with a category (the CLI maps
// each to its own exit code, app/exit_codes.h; the Python module to its own
// exception class) is the program's own.
#pragma once

#include <stdexcept>
#include <string>

namespace foldfill {

// The category of a failure.
enum class ErrorKind {
  Usage,                // bad options, arguments or options file; an id that names nothing
  CannotRead,           // missing or unreadable input file
  BadFormat,            // empty, garbage, truncated or unsupported file content
  NonFiniteCoordinate,  // NaN or infinite vertex coordinate
  BadFace,              // index out of range, fewer than 3 or repeated vertices
  NonManifold,          // an edge with more than two faces, or a pinched vertex
  NotADisk,             // a selected hole loop that is not a disk boundary
  FillFailed,           // a stage of the fill could not produce a valid patch
  CannotWrite,          // output could not be written
  Internal,             // a bug: should never happen
};

// An identifier: "usage", "cannot_read", "bad_format", "non_finite_coordinate",
// "bad_face", "non_manifold", "not_a_disk", "fill_failed", "cannot_write",
// "internal".
const char* to_string(ErrorKind kind);

// An error with its kind. `what()` is one line: "FILE: problem" when a file is
// concerned, so that a program can print it as is.
class Error : public std::runtime_error {
 public:
  Error(ErrorKind kind, const std::string& message) : std::runtime_error(message), kind_(kind) {}
  ErrorKind kind() const { return kind_; }

 private:
  ErrorKind kind_;
};

}  // namespace foldfill

// The errors of foldfill: Error, whose kind says the category of the failure,
// and one subclass of it per category, so that a caller can catch the
// categories it handles by type and the rest as Error. What a program does
// with a category (the CLI maps each to its own exit code, app/exit_codes.h;
// the Python module to its own exception class) is the program's own.
//
//   Error
//   ├── UsageError                (ErrorKind::Usage)
//   ├── CannotReadError           (ErrorKind::CannotRead)
//   ├── InputError                (a mesh foldfill cannot work on)
//   │   ├── BadFormatError           (ErrorKind::BadFormat)
//   │   ├── NonFiniteCoordinateError (ErrorKind::NonFiniteCoordinate)
//   │   ├── BadFaceError             (ErrorKind::BadFace)
//   │   ├── NonManifoldError         (ErrorKind::NonManifold)
//   │   └── NotADiskError            (ErrorKind::NotADisk)
//   ├── FillFailedError           (ErrorKind::FillFailed)
//   ├── CannotWriteError          (ErrorKind::CannotWrite)
//   └── InternalError             (ErrorKind::Internal)
//
// An Error is always one of the leaf classes (or derived from one), and its
// kind() is the one its class names; throw_error throws the class of a kind
// known only at run time.
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
// concerned, so that a program can print it as is. Constructed only through
// its subclasses, so that the class and the kind always agree.
class Error : public std::runtime_error {
 public:
  ErrorKind kind() const { return kind_; }

 protected:
  Error(ErrorKind kind, const std::string& message) : std::runtime_error(message), kind_(kind) {}

 private:
  ErrorKind kind_;
};

// Throws the subclass of Error whose kind is `kind`, with `message`.
[[noreturn]] void throw_error(ErrorKind kind, const std::string& message);

// Bad options, arguments or options file; an id or point that names nothing.
class UsageError : public Error {
 public:
  explicit UsageError(const std::string& message) : Error(ErrorKind::Usage, message) {}
};

// An input file that is missing or cannot be read.
class CannotReadError : public Error {
 public:
  explicit CannotReadError(const std::string& message) : Error(ErrorKind::CannotRead, message) {}
};

// A mesh, or a part of it named to be filled, that foldfill cannot work on:
// the base of the five kinds about a mesh's content.
class InputError : public Error {
 protected:
  using Error::Error;
};

// Empty, garbage, truncated or unsupported file content.
class BadFormatError : public InputError {
 public:
  explicit BadFormatError(const std::string& message) : InputError(ErrorKind::BadFormat, message) {}
};

// A vertex with a NaN or infinite coordinate.
class NonFiniteCoordinateError : public InputError {
 public:
  explicit NonFiniteCoordinateError(const std::string& message)
      : InputError(ErrorKind::NonFiniteCoordinate, message) {}
};

// A face with a vertex index out of range, fewer than 3 or repeated vertices.
class BadFaceError : public InputError {
 public:
  explicit BadFaceError(const std::string& message) : InputError(ErrorKind::BadFace, message) {}
};

// An edge with more than two faces, or a pinched vertex.
class NonManifoldError : public InputError {
 public:
  explicit NonManifoldError(const std::string& message)
      : InputError(ErrorKind::NonManifold, message) {}
};

// A hole loop selected to be filled that is not the boundary of a disk.
class NotADiskError : public InputError {
 public:
  explicit NotADiskError(const std::string& message) : InputError(ErrorKind::NotADisk, message) {}
};

// A stage of the fill could not produce a valid patch (or the fill was
// cancelled).
class FillFailedError : public Error {
 public:
  explicit FillFailedError(const std::string& message) : Error(ErrorKind::FillFailed, message) {}
};

// An output that could not be written.
class CannotWriteError : public Error {
 public:
  explicit CannotWriteError(const std::string& message) : Error(ErrorKind::CannotWrite, message) {}
};

// A bug in foldfill: a broken invariant that should never happen.
class InternalError : public Error {
 public:
  explicit InternalError(const std::string& message) : Error(ErrorKind::Internal, message) {}
};

}  // namespace foldfill

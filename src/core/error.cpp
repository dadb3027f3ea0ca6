#include "foldfill/error.h"

namespace foldfill {

const char* to_string(ErrorKind kind) {
  switch (kind) {
    case ErrorKind::Usage:
      return "usage";
    case ErrorKind::CannotRead:
      return "cannot_read";
    case ErrorKind::BadFormat:
      return "bad_format";
    case ErrorKind::NonFiniteCoordinate:
      return "non_finite_coordinate";
    case ErrorKind::BadFace:
      return "bad_face";
    case ErrorKind::NonManifold:
      return "non_manifold";
    case ErrorKind::NotADisk:
      return "not_a_disk";
    case ErrorKind::FillFailed:
      return "fill_failed";
    case ErrorKind::CannotWrite:
      return "cannot_write";
    case ErrorKind::Internal:
      return "internal";
  }
  return "internal";
}

void throw_error(ErrorKind kind, const std::string& message) {
  switch (kind) {
    case ErrorKind::Usage:
      throw UsageError(message);
    case ErrorKind::CannotRead:
      throw CannotReadError(message);
    case ErrorKind::BadFormat:
      throw BadFormatError(message);
    case ErrorKind::NonFiniteCoordinate:
      throw NonFiniteCoordinateError(message);
    case ErrorKind::BadFace:
      throw BadFaceError(message);
    case ErrorKind::NonManifold:
      throw NonManifoldError(message);
    case ErrorKind::NotADisk:
      throw NotADiskError(message);
    case ErrorKind::FillFailed:
      throw FillFailedError(message);
    case ErrorKind::CannotWrite:
      throw CannotWriteError(message);
    case ErrorKind::Internal:
      throw InternalError(message);
  }
  throw InternalError(message);
}

}  // namespace foldfill

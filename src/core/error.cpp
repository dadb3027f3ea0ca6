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

}  // namespace foldfill

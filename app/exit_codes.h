// The CLI's exit codes (README, "Exit codes"): one per kind of library error,
// and the CLI's own.
#pragma once

#include "foldfill/error.h"

namespace foldfill::cli {

// The exit code of a failure of `kind`: 1 for an internal error, 2 to 10 for
// the others.
constexpr int exit_code(ErrorKind kind) {
  switch (kind) {
    case ErrorKind::Internal:
      return 1;
    case ErrorKind::Usage:
      return 2;
    case ErrorKind::CannotRead:
      return 3;
    case ErrorKind::BadFormat:
      return 4;
    case ErrorKind::NonFiniteCoordinate:
      return 5;
    case ErrorKind::BadFace:
      return 6;
    case ErrorKind::NonManifold:
      return 7;
    case ErrorKind::NotADisk:
      return 8;
    case ErrorKind::FillFailed:
      return 9;
    case ErrorKind::CannotWrite:
      return 10;
  }
  return 1;
}

// A batch in which some files failed.
constexpr int kBatchFailedExitCode = 11;

}  // namespace foldfill::cli

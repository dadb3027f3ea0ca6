// Whole-file reading and atomic writing.
//
// A file is written into an unnamed file in the target's folder (Linux's
// O_TMPFILE), which is then linked under a short temporary name and renamed
// over the target: a process killed while writing, even by SIGKILL, leaves
// nothing behind (except in the instant between the link and the rename). Where
// the file system has no unnamed files, a named one, `.foldfill-XXXXXX`, is
// written instead and recorded for unlink_pending_temporaries. The temporary
// name is short so that any valid target name works.
#include "foldfill/file.h"

#include <fcntl.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "foldfill/error.h"

namespace foldfill {
namespace {

// The named temporary files of the writes in progress, for a signal handler:
// fixed storage, and a slot's name is read only while its state says so.
constexpr int kPendingSlots = 64;
constexpr size_t kTemporaryNameBytes = 32;
enum SlotState : int { kFree, kClaimed, kNamed };
static_assert(std::atomic<int>::is_always_lock_free);

struct PendingTemporary {
  std::atomic<int> state{kFree};
  int folder = -1;  // the folder's descriptor
  char name[kTemporaryNameBytes] = {};
};
PendingTemporary pending[kPendingSlots];

// Records `name` in `folder`; returns its slot, or -1 when every slot is taken
// (the file is then not removed on a signal).
int record_pending(int folder, const std::string& name) {
  if (name.size() >= kTemporaryNameBytes) return -1;
  for (int slot = 0; slot < kPendingSlots; ++slot) {
    int expected = kFree;
    if (!pending[slot].state.compare_exchange_strong(expected, kClaimed)) continue;
    pending[slot].folder = folder;
    std::memcpy(pending[slot].name, name.c_str(), name.size() + 1);
    pending[slot].state.store(kNamed);
    return slot;
  }
  return -1;
}

void forget_pending(int slot) {
  if (slot >= 0) pending[slot].state.store(kFree);
}

// A file descriptor, closed when it goes.
class Descriptor {
 public:
  explicit Descriptor(int fd = -1) : fd_(fd) {}
  Descriptor(const Descriptor&) = delete;
  Descriptor& operator=(const Descriptor&) = delete;
  ~Descriptor() { reset(); }
  int get() const { return fd_; }
  explicit operator bool() const { return fd_ >= 0; }
  // Closes now; false (errno set) when close reports an error (a late write error).
  bool reset() {
    const int fd = fd_;
    fd_ = -1;
    return fd < 0 || ::close(fd) == 0;
  }
  void assign(int fd) {
    reset();
    fd_ = fd;
  }

 private:
  int fd_;
};

[[noreturn]] void fail(const std::string& path, int error) {
  throw CannotWriteError(path + ": cannot write (" + std::strerror(error) + ")");
}

// `.foldfill-` and six characters, different at each call.
std::string temporary_name() {
  static std::atomic<unsigned long long> counter{0};
  static const char kDigits[] = "0123456789ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz";
  unsigned long long bits =
      (counter++ * 0x9E3779B97F4A7C15ull) ^
      static_cast<unsigned long long>(std::chrono::steady_clock::now().time_since_epoch().count()) ^
      (static_cast<unsigned long long>(::getpid()) << 32);
  std::string name = ".foldfill-";
  for (int i = 0; i < 6; ++i, bits /= 62) name += kDigits[bits % 62];
  return name;
}

#ifdef O_PATH
constexpr int kFolderFlags = O_PATH | O_DIRECTORY | O_CLOEXEC;
#else
constexpr int kFolderFlags = O_RDONLY | O_DIRECTORY | O_CLOEXEC;
#endif

// Writes all of `bytes`; false with errno set on failure.
bool write_all(int fd, std::string_view bytes) {
  while (!bytes.empty()) {
    const ssize_t n = ::write(fd, bytes.data(), bytes.size());
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) return false;
    if (n == 0) {
      errno = ENOSPC;
      return false;
    }
    bytes.remove_prefix(static_cast<size_t>(n));
  }
  return true;
}

// A temporary file beside the target: unnamed until commit(), or named from
// the start. Removed unless it was renamed into place.
class TemporaryFile {
 public:
  explicit TemporaryFile(const std::string& path) : path_(path) {
    const std::filesystem::path target(path);
    target_name_ = target.filename().string();
    if (target_name_.empty() || target_name_ == "." || target_name_ == "..") fail(path, EISDIR);
    const std::string folder = target.has_parent_path() ? target.parent_path().string() : ".";
    folder_.assign(::open(folder.c_str(), kFolderFlags));
    if (!folder_) fail(path, errno);
#ifdef O_TMPFILE
    // An unnamed file is linked into place through /proc/self/fd.
    static const bool proc_fd = ::access("/proc/self/fd", X_OK) == 0;
    if (proc_fd) {
      file_.assign(::openat(folder_.get(), ".", O_TMPFILE | O_WRONLY | O_CLOEXEC, 0666));
      if (file_) return;
      // Old kernels and some file systems have no unnamed files.
      if (errno != EOPNOTSUPP && errno != EISDIR && errno != EINVAL) fail(path, errno);
    }
#endif
    // The mode is that of any new file: 0666 less the umask.
    file_.assign(create_named([&](const char* name) {
      return ::openat(folder_.get(), name, O_CREAT | O_EXCL | O_WRONLY | O_CLOEXEC, 0666);
    }));
  }

  TemporaryFile(const TemporaryFile&) = delete;
  TemporaryFile& operator=(const TemporaryFile&) = delete;

  ~TemporaryFile() {
    file_.reset();
    if (!name_.empty()) ::unlinkat(folder_.get(), name_.c_str(), 0);
    forget_pending(slot_);
  }

  int fd() const { return file_.get(); }

  // Gives the written file a temporary name (when it has none), closes it and
  // renames it over the target.
  void commit() {
    if (name_.empty()) {
      const std::string self = "/proc/self/fd/" + std::to_string(file_.get());
      create_named([&](const char* name) {
        const int linked = ::linkat(AT_FDCWD, self.c_str(), folder_.get(), name, AT_SYMLINK_FOLLOW);
#ifdef AT_EMPTY_PATH
        // Without /proc/self/fd after all; this needs CAP_DAC_READ_SEARCH.
        if (linked < 0 && errno == ENOENT) {
          return ::linkat(file_.get(), "", folder_.get(), name, AT_EMPTY_PATH);
        }
#endif
        return linked;
      });
    }
    if (!file_.reset()) fail(path_, errno);  // a late error (disk full) shows up here
    if (::renameat(folder_.get(), name_.c_str(), folder_.get(), target_name_.c_str()) != 0) {
      fail(path_, errno);
    }
    name_.clear();
    forget_pending(slot_);
    slot_ = -1;
  }

 private:
  // Runs `create` (an open or a link: < 0 with errno on failure) with new
  // temporary names until one is free, records the name, returns the result.
  template <class Create>
  int create_named(const Create& create) {
    for (int attempt = 0; attempt < 100; ++attempt) {
      const std::string name = temporary_name();
      const int result = create(name.c_str());
      if (result < 0 && errno == EEXIST) continue;
      if (result < 0) fail(path_, errno);
      name_ = name;
      slot_ = record_pending(folder_.get(), name_);
      return result;
    }
    fail(path_, EEXIST);
  }

  std::string path_, target_name_;
  Descriptor folder_, file_;
  std::string name_;  // the temporary name, while the file has one
  int slot_ = -1;     // its record for unlink_pending_temporaries, or -1
};

}  // namespace

std::string read_file(const std::string& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) {
    throw CannotReadError(path + ": is a directory, not a mesh file");
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) throw CannotReadError(path + ": cannot open (" + std::strerror(errno) + ")");
  std::string bytes;
  in.seekg(0, std::ios::end);
  const std::streamoff size = in.tellg();
  if (size > 0) {
    bytes.resize(static_cast<size_t>(size));
    in.seekg(0);
    in.read(bytes.data(), size);
  }
  if (!in) throw CannotReadError(path + ": read failed");
  return bytes;
}

void write_file_atomically(const std::string& path, std::string_view bytes) {
  write_file_atomically(path, [bytes](const ByteConsumer& write) { write(bytes); });
}

void write_file_atomically(const std::string& path,
                           const std::function<void(const ByteConsumer&)>& produce) {
  TemporaryFile file(path);
  produce([&](std::string_view piece) {
    if (!write_all(file.fd(), piece)) fail(path, errno);
  });
  file.commit();
}

void unlink_pending_temporaries() noexcept {
  for (PendingTemporary& slot : pending) {
    if (slot.state.load() == kNamed) ::unlinkat(slot.folder, slot.name, 0);
  }
}

}  // namespace foldfill

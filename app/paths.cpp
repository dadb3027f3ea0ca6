// The paths a command reads and writes, checked before any work.
#include "paths.h"

#include <sys/stat.h>
#include <unistd.h>

#include <cctype>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <map>
#include <set>

#include "foldfill/error.h"

namespace fs = std::filesystem;

namespace foldfill::cli {
namespace {

// Absolute, with the symbolic links and `..` of the part that exists
// resolved and the rest normalised, without a trailing separator.
std::string resolved_path(const fs::path& path) {
  std::error_code ec;
  fs::path resolved = fs::weakly_canonical(path, ec);
  if (ec) {
    resolved = fs::absolute(path, ec).lexically_normal();
    if (ec) resolved = path.lexically_normal();
  }
  std::string text = resolved.string();
  while (text.size() > 1 && text.back() == '/') text.pop_back();
  return text;
}

fs::path folder_of(const fs::path& path) {
  return path.has_parent_path() ? path.parent_path() : fs::path(".");
}

// A file name that write_flat_meshes writes: loopID_flat_strip.obj or
// loopID_flat_patch.obj.
bool is_flat_mesh_name(const std::string& name) {
  const std::string prefix = "loop";
  if (name.compare(0, prefix.size(), prefix) != 0) return false;
  size_t end = prefix.size();
  while (end < name.size() && std::isdigit(static_cast<unsigned char>(name[end]))) ++end;
  const size_t digits = end - prefix.size();
  if (digits == 0 || (digits > 1 && name[prefix.size()] == '0')) return false;
  const std::string rest = name.substr(end);
  return rest == "_flat_strip.obj" || rest == "_flat_patch.obj";
}

[[noreturn]] void cannot_write(const std::string& path, const std::string& reason) {
  throw CannotWriteError(path + ": " + reason);
}

// Walks up from `path` to the first part that exists: it must be a writable folder.
void check_folder_can_be_made(const std::string& path) {
  fs::path part = path;
  for (;;) {
    struct stat status {};
    if (::stat(part.c_str(), &status) == 0) {
      const bool itself = part == fs::path(path);
      if (!S_ISDIR(status.st_mode)) {
        cannot_write(path,
                     itself ? "cannot create the folder (a file is in the way)"
                            : "cannot create the folder (" + part.string() + " is not a folder)");
      }
      if (::access(part.c_str(), W_OK | X_OK) != 0) {
        cannot_write(path, std::string(itself ? "cannot write into the folder ("
                                              : "cannot create the folder (") +
                               std::strerror(errno) + ")");
      }
      return;
    }
    if (errno != ENOENT && errno != ENOTDIR) {
      cannot_write(path, std::string("cannot create the folder (") + std::strerror(errno) + ")");
    }
    if (part.has_parent_path() && part.parent_path() != part) {
      part = part.parent_path();
    } else if (part.is_relative() && part != ".") {
      part = ".";
    } else {
      cannot_write(path, "cannot create the folder (no folder above it exists)");
    }
  }
}

}  // namespace

void PathPlan::reads(const std::string& path, const std::string& what) {
  add(Use::Read, path, what);
}
void PathPlan::writes_file(const std::string& path, const std::string& what) {
  add(Use::File, path, what);
}
void PathPlan::writes_folder(const std::string& path, const std::string& what) {
  add(Use::Folder, path, what);
}
void PathPlan::writes_flat_folder(const std::string& path, const std::string& what) {
  add(Use::FlatFolder, path, what);
}

void PathPlan::add(Use use, const std::string& path, const std::string& what) {
  if (path.empty()) return;
  Entry entry{use, path, what, resolved_path(path), resolved_path(folder_of(path)), {}};
  struct stat status {};
  if (::stat(path.c_str(), &status) == 0) {
    entry.id = std::make_pair(static_cast<unsigned long>(status.st_dev),
                              static_cast<unsigned long>(status.st_ino));
  }
  entries_.push_back(std::move(entry));
}

void PathPlan::check() const {
  check_same_files();
  check_flat_meshes();
  std::set<std::string> made_folders;
  for (const Entry& entry : entries_) {
    if (entry.use == Use::Folder || entry.use == Use::FlatFolder)
      made_folders.insert(entry.resolved);
  }
  for (const Entry& entry : entries_) check_writable(entry, made_folders);
}

// Each entry against the earlier ones, by resolved path and by device and
// inode. Two inputs may be one file, and two folders one folder.
void PathPlan::check_same_files() const {
  const auto is_folder = [](const Entry& e) {
    return e.use == Use::Folder || e.use == Use::FlatFolder;
  };
  std::map<std::string, const Entry*> by_path;
  std::map<std::pair<unsigned long, unsigned long>, const Entry*> by_id;
  for (const Entry& entry : entries_) {
    const Entry* earlier = nullptr;
    if (const auto found = by_path.find(entry.resolved); found != by_path.end()) {
      earlier = found->second;
    } else if (entry.id) {
      if (const auto same = by_id.find(*entry.id); same != by_id.end()) earlier = same->second;
    }
    const bool both_read = earlier && earlier->use == Use::Read && entry.use == Use::Read;
    if (earlier && !both_read && !(is_folder(*earlier) && is_folder(entry))) {
      // The message is about the path written (the later one when both are).
      const Entry& written = entry.use == Use::Read ? *earlier : entry;
      const Entry& other = entry.use == Use::Read ? entry : *earlier;
      throw UsageError(written.path + ": " + written.what + " would be the same file as " +
                       other.what + (other.path == written.path ? "" : " " + other.path) +
                       (other.use == Use::Read ? "; an input is never overwritten" : ""));
    }
    by_path.emplace(entry.resolved, &entry);
    if (entry.id) by_id.emplace(*entry.id, &entry);
  }
}

// No file read or written may be one of the flat meshes a flat folder gets,
// named as it is given or as it resolves.
void PathPlan::check_flat_meshes() const {
  std::map<std::string, const Entry*> flat_folders;
  for (const Entry& entry : entries_) {
    if (entry.use == Use::FlatFolder) flat_folders.emplace(entry.resolved, &entry);
  }
  if (flat_folders.empty()) return;
  for (const Entry& entry : entries_) {
    if (entry.use != Use::Read && entry.use != Use::File) continue;
    const fs::path resolved = entry.resolved;
    const std::pair<std::string, std::string> places[] = {
        {entry.folder, fs::path(entry.path).filename().string()},
        {resolved.parent_path().string(), resolved.filename().string()}};
    for (const auto& [folder, name] : places) {
      const auto flat = flat_folders.find(folder);
      if (flat == flat_folders.end() || !is_flat_mesh_name(name)) continue;
      throw UsageError(entry.path + ": " + entry.what +
                       " would be the same file as a flat mesh of " + flat->second->what + " " +
                       flat->second->path +
                       (entry.use == Use::Read ? "; an input is never overwritten" : ""));
    }
  }
}

void PathPlan::check_writable(const Entry& entry, const std::set<std::string>& made_folders) const {
  if (entry.use == Use::Read) return;
  if (entry.use != Use::File) {
    check_folder_can_be_made(entry.path);
    return;
  }
  struct stat status {};
  if (::stat(entry.path.c_str(), &status) == 0 && !S_ISREG(status.st_mode)) {
    cannot_write(entry.path, S_ISDIR(status.st_mode) ? "cannot write (is a folder)"
                                                     : "cannot write (not a regular file)");
  }
  // A file in a folder of the plan: that folder is checked, and made.
  if (made_folders.count(entry.folder) > 0) return;
  const std::string folder = folder_of(entry.path).string();
  if (::stat(folder.c_str(), &status) != 0) {
    cannot_write(entry.path, errno == ENOENT || errno == ENOTDIR
                                 ? "cannot write (no folder " + folder + ")"
                                 : std::string("cannot write (") + std::strerror(errno) + ")");
  }
  if (!S_ISDIR(status.st_mode)) {
    cannot_write(entry.path, "cannot write (" + folder + " is not a folder)");
  }
  if (::access(folder.c_str(), W_OK | X_OK) != 0) {
    cannot_write(entry.path, std::string("cannot write (") + std::strerror(errno) + ")");
  }
}

}  // namespace foldfill::cli

// The paths a command reads and writes, checked before any work: no path
// written may be an input or another path written, and each must be
// writable.
#pragma once

#include <optional>
#include <set>
#include <string>
#include <utility>
#include <vector>

namespace foldfill::cli {

class PathPlan {
 public:
  // `what` names the path's part in messages: "the input file", "the report".
  void reads(const std::string& path, const std::string& what);
  void writes_file(const std::string& path, const std::string& what);
  // A folder created when missing.
  void writes_folder(const std::string& path, const std::string& what);
  // A folder created when missing, into which the flat meshes of --flat-dir
  // are written (loopID_flat_strip.obj, loopID_flat_patch.obj).
  void writes_flat_folder(const std::string& path, const std::string& what);

  // Throws UsageError, "PATH: ...", when a path written is the same file or
  // folder as an input or as another path written (through a symbolic or a
  // hard link, or a `..`, whether it exists yet or not), or a flat mesh of a
  // flat folder would be; then CannotWriteError when a file written is not
  // a regular file or its folder is missing or not writable, or a folder
  // cannot be created.
  void check() const;

 private:
  enum class Use { Read, File, Folder, FlatFolder };
  struct Entry {
    Use use;
    std::string path, what;
    std::string resolved;  // absolute, symbolic links and `..` resolved as far as it exists
    // The folder that holds the entry itself (a symbolic link not followed), resolved.
    std::string folder;
    std::optional<std::pair<unsigned long, unsigned long>> id;  // device and inode, if it exists
  };

  void add(Use use, const std::string& path, const std::string& what);
  void check_same_files() const;
  void check_flat_meshes() const;
  void check_writable(const Entry& entry, const std::set<std::string>& made_folders) const;

  std::vector<Entry> entries_;
};

}  // namespace foldfill::cli

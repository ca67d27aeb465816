#include "puppet/compare/output_folder.h"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>

#include "puppet/model/text.h"

namespace puppet::compare {
namespace fs = std::filesystem;

namespace {

// the pid written in a lock file, for the refusal's message
std::string lock_holder(int fd) {
  char text[32] = {};
  const ssize_t got = ::pread(fd, text, sizeof text - 1, 0);
  std::string pid = got > 0 ? std::string(text, static_cast<size_t>(got)) : "";
  pid.erase(std::remove_if(pid.begin(), pid.end(), [](char c) { return c < '0' || c > '9'; }),
            pid.end());
  return pid.empty() ? "" : " (pid " + pid + ")";
}

// The lock at `lock`, taken without waiting: an open, locked, regular file, and the one the name
// still names (one that was removed while we waited is not the lock). Its descriptor; `fail`
// (which throws) says why not.
template <typename Fail>
int lock_exclusively(const fs::path& lock, const Fail& fail) {
  int fd = -1;
  for (;;) {
    // never through a link planted at the lock's name: its target would be truncated
    fd = ::open(lock.c_str(), O_RDWR | O_CREAT | O_CLOEXEC | O_NOFOLLOW, 0644);
    if (fd < 0 && errno == ELOOP) {
      fail("cannot be locked: its lock " + shown(lock.filename().string()) +
           " is a symbolic link, which is never written through (remove it)");
    }
    if (fd < 0) fail(std::string("cannot be locked (") + std::strerror(errno) + ")");
    struct stat opened {};
    if (::fstat(fd, &opened) == 0 && !S_ISREG(opened.st_mode)) {
      ::close(fd);
      fd = -1;
      fail("cannot be locked: its lock " + shown(lock.filename().string()) +
           " is not a regular file (remove it)");
    }
    if (::flock(fd, LOCK_EX | LOCK_NB) != 0) {
      const std::string holder = lock_holder(fd);
      ::close(fd);
      fd = -1;
      fail("is being written by another command" + holder + "; wait for it or choose another");
    }
    struct stat held {
    }, named{};
    if (::fstat(fd, &held) == 0 && ::stat(lock.c_str(), &named) == 0 &&
        held.st_ino == named.st_ino && held.st_dev == named.st_dev) {
      return fd;
    }
    ::close(fd);
  }
}

}  // namespace

OutputFolder::OutputFolder(const std::string& flag, const std::string& path,
                           std::vector<std::string> owned) {
  auto fail = [&](const std::string& problem) {
    throw OutputError(flag + ": " + shown(path) + " " + problem);
  };
  if (path.empty()) throw OutputError(flag + ": an empty path (name the results' folder)");
  if (path.size() > 1024) fail("is longer than 1024 bytes");
  std::error_code error;
  fs::path absolute = fs::absolute(fs::path(path), error).lexically_normal();
  if (error) fail("cannot be resolved (the working folder: " + error.message() + ")");
  if (!absolute.has_filename()) absolute = absolute.parent_path();  // "results/x/"
  const std::string name = absolute.filename().string();
  if (name.empty() || name == "." || name == ".." || absolute == absolute.root_path()) {
    fail("is not a folder of its own (it is replaced whole)");
  }
  // the staging folder's name adds ".", ".staging-" and a pid to the folder's: checked before
  // anything is made, so that a name the file system allows but the staging name does not is
  // refused without leaving folders behind
  constexpr size_t kNameMax = 255, kStagingExtra = 1 + 9 + 10;
  if (name.size() + kStagingExtra > kNameMax) {
    fail("has a name of " + std::to_string(name.size()) + " bytes; at most " +
         std::to_string(kNameMax - kStagingExtra) + " (its staging folder's name is longer)");
  }
  path_ = absolute;
  const fs::path parent = absolute.parent_path();
  // the parent folders this command makes, removed again if it is refused below
  fs::path made;
  for (fs::path p = parent; !p.empty() && p != p.root_path(); p = p.parent_path()) {
    if (fs::exists(fs::symlink_status(p, error))) break;
    made = p;
  }
  error.clear();
  struct Unmake {
    fs::path folder;
    bool keep = false;
    ~Unmake() {
      std::error_code ignored;
      if (!keep && !folder.empty()) fs::remove_all(folder, ignored);
    }
  } unmake{made};
  fs::create_directories(parent, error);
  if (error || !fs::is_directory(parent)) fail("cannot be made (" + error.message() + ")");
  if (::access(parent.c_str(), W_OK | X_OK) != 0) {
    fail("cannot be written: its parent folder is not writable (" +
         std::string(std::strerror(errno)) + ")");
  }

  // what is there: the command's own files, or nothing
  const fs::file_status status = fs::symlink_status(absolute, error);
  if (fs::exists(status)) {
    if (!fs::is_directory(status)) fail("exists and is not a folder");
    for (const fs::directory_entry& entry : fs::directory_iterator(absolute, error)) {
      const std::string entry_name = entry.path().filename().string();
      if (std::find(owned.begin(), owned.end(), entry_name) == owned.end()) {
        fail("holds " + shown(entry_name) +
             ", which this command does not write; the folder is replaced whole, so choose a new "
             "or empty one");
      }
    }
    if (error) fail("cannot be read (" + error.message() + ")");
  }

  // the lock: an open, locked file; one that was removed while we waited is not the lock
  lock_ = parent / ("." + name + ".lock");
  lock_fd_ = lock_exclusively(lock_, fail);
  tidy_lock_.emplace(lock_);
  const std::string pid = std::to_string(::getpid()) + "\n";
  if (::ftruncate(lock_fd_, 0) != 0 || ::pwrite(lock_fd_, pid.data(), pid.size(), 0) < 0) {
    // the pid only serves the refusal's message
  }

  // staging folders of commands that died (the lock is ours: no live command owns one)
  const std::string stale_prefix = "." + name + ".staging-";
  for (const fs::directory_entry& entry : fs::directory_iterator(parent, error)) {
    if (entry.path().filename().string().rfind(stale_prefix, 0) == 0) {
      fs::remove_all(entry.path(), error);
    }
  }
  staging_ = parent / (stale_prefix + std::to_string(::getpid()));
  fs::remove_all(staging_, error);
  error.clear();
  tidy_staging_.emplace(staging_);
  if (!fs::create_directory(staging_, error) && !error) {
    error = std::make_error_code(std::errc::file_exists);
  }
  if (error) {
    tidy_staging_.reset();
    tidy_lock_.reset();
    ::unlink(lock_.c_str());
    ::close(lock_fd_);
    fail("cannot be written (" + error.message() + ")");
  }
  unmake.keep = true;
}

void OutputFolder::commit() {
  // the stop watchdog waits for the swap to end before it tidies and exits
  const std::unique_lock<std::mutex> guard = commit_guard();
  throw_if_cancelled();  // a signal while the results were written: the old ones stay
  std::error_code error;
  if (fs::exists(fs::symlink_status(path_, error))) {
    // one rename swaps the old results and the new: the folder is never missing or mixed
    if (::renameat2(AT_FDCWD, staging_.c_str(), AT_FDCWD, path_.c_str(), RENAME_EXCHANGE) != 0) {
      throw std::runtime_error(path_.string() + ": cannot replace the results (" +
                               std::strerror(errno) + ")");
    }
    fs::remove_all(staging_, error);  // the old results
  } else if (::renameat2(AT_FDCWD, staging_.c_str(), AT_FDCWD, path_.c_str(), RENAME_NOREPLACE) !=
             0) {
    throw std::runtime_error(path_.string() + ": cannot place the results (" +
                             std::strerror(errno) + ")");
  }
  committed_ = true;
}

OutputFolder::~OutputFolder() {
  std::error_code error;
  if (!committed_ && !staging_.empty()) fs::remove_all(staging_, error);
  if (lock_fd_ >= 0) {
    ::unlink(lock_.c_str());  // while held: a waiter that opened it sees another inode
    ::close(lock_fd_);
    lock_fd_ = -1;
  }
}

}  // namespace puppet::compare

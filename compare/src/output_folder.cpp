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

}  // namespace

OutputFolder::OutputFolder(const std::string& flag, const std::string& path,
                           std::vector<std::string> owned) {
  auto fail = [&](const std::string& problem) {
    throw OutputError(flag + ": " + shown(path) + " " + problem);
  };
  if (path.empty()) throw OutputError(flag + ": an empty path (name the results' folder)");
  if (path.size() > 1024) fail("is longer than 1024 bytes");
  fs::path absolute = fs::absolute(fs::path(path)).lexically_normal();
  if (!absolute.has_filename()) absolute = absolute.parent_path();  // "results/x/"
  const std::string name = absolute.filename().string();
  if (name.empty() || name == "." || name == ".." || absolute == absolute.root_path()) {
    fail("is not a folder of its own (it is replaced whole)");
  }
  path_ = absolute;
  const fs::path parent = absolute.parent_path();
  std::error_code error;
  fs::create_directories(parent, error);
  if (error || !fs::is_directory(parent)) fail("cannot be made (" + error.message() + ")");

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
  for (;;) {
    lock_fd_ = ::open(lock_.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
    if (lock_fd_ < 0) fail(std::string("cannot be locked (") + std::strerror(errno) + ")");
    if (::flock(lock_fd_, LOCK_EX | LOCK_NB) != 0) {
      const std::string holder = lock_holder(lock_fd_);
      ::close(lock_fd_);
      lock_fd_ = -1;
      fail("is being written by another command" + holder + "; wait for it or choose another");
    }
    struct stat held {
    }, named{};
    if (::fstat(lock_fd_, &held) == 0 && ::stat(lock_.c_str(), &named) == 0 &&
        held.st_ino == named.st_ino && held.st_dev == named.st_dev) {
      break;
    }
    ::close(lock_fd_);
  }
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
  fs::create_directory(staging_, error);
  if (error) {
    ::unlink(lock_.c_str());
    ::close(lock_fd_);
    fail("cannot be written (" + error.message() + ")");
  }
}

void OutputFolder::commit() {
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

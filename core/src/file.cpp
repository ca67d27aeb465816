#include "puppet/model/file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

namespace puppet {

bool read_regular_file(const std::string& path, size_t max_bytes, std::string* text,
                       std::string* problem) {
  // O_NONBLOCK: opening a FIFO for reading would otherwise wait for a writer
  const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) {
    *problem = std::string("cannot open the file (") + std::strerror(errno) + ")";
    return false;
  }
  struct Closer {
    int fd;
    ~Closer() { ::close(fd); }
  } closer{fd};
  struct stat info {};
  if (::fstat(fd, &info) != 0 || !S_ISREG(info.st_mode)) {
    *problem = S_ISDIR(info.st_mode) ? "is a folder, not a file"
                                     : "is not a regular file (a FIFO, a device or a socket)";
    return false;
  }
  if (static_cast<unsigned long long>(info.st_size) > max_bytes) {
    *problem = "is " + std::to_string(info.st_size) + " bytes (at most " +
               std::to_string(max_bytes) + " are read)";
    return false;
  }
  text->clear();
  text->reserve(static_cast<size_t>(info.st_size));
  char buffer[65536];
  for (;;) {
    const ssize_t got = ::read(fd, buffer, sizeof buffer);
    if (got < 0 && errno == EINTR) continue;
    if (got < 0) {
      *problem = std::string("cannot read the file (") + std::strerror(errno) + ")";
      return false;
    }
    if (got == 0) break;
    if (text->size() + static_cast<size_t>(got) > max_bytes) {  // it grew while being read
      *problem = "grew past " + std::to_string(max_bytes) + " bytes while being read";
      return false;
    }
    text->append(buffer, static_cast<size_t>(got));
  }
  return true;
}

}  // namespace puppet

/// \file
/// Reading a user's file with bounds: only a regular file (not a FIFO, a device or a folder, which
/// could block or never end) and only up to a stated size, so that no input makes a reader hang
/// or run out of memory.
#pragma once

#include <cstddef>
#include <string>

namespace puppet {

/// The whole content of the regular file at `path`, up to `max_bytes`. On failure returns false
/// and sets `problem` to what went wrong, without the path ("is not a regular file", ...).
bool read_regular_file(const std::string& path, size_t max_bytes, std::string* text,
                       std::string* problem);

}  // namespace puppet

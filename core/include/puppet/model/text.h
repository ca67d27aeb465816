/// \file
/// Text from a file or a command line, made fit for a one-line message.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

namespace puppet {

/// bytes outside printable ASCII as `\xNN`, cut after max_length characters
/// with "...", so that a message stays one bounded line whatever it quotes
std::string printable(std::string_view text, size_t max_length);
/// a message as one line of at most max_length characters: control bytes as '?', a longer one
/// cut and ended with "..."
/// (a last guard where messages are printed; the texts they quote went through shown())
std::string one_line(std::string_view text, size_t max_length);
/// printable(text, 64) in double quotes (a quote inside as `\x22`)
std::string shown(std::string_view text);

}  // namespace puppet

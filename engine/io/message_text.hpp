#pragma once
// The one home for keeping an error message one short line: lists of names are shortened to
// their first few entries and "… and N more", and a line that is still too long is cut (at a
// UTF-8 character boundary) with the count of bytes left out. Used by the loaders, the spec
// checks and armfarm's last-resort printing of an error (runner/cli/main.cpp).
#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

namespace armfarm {

/// How many entries a message lists before "… and N more".
inline constexpr std::size_t kListedItems = 10;

/// The longest error line armfarm prints, bytes; longer lines are cut by cap_message_line.
inline constexpr std::size_t kMaxMessageBytes = 1000;

/// `items` joined with `separator`; past the first `shown`, " … and N more" replaces the rest.
std::string join_shortened(const std::vector<std::string>& items, std::string_view separator = ", ",
                           std::size_t shown = kListedItems);

/// `text` when it is at most `max_bytes` long; else its first bytes up to a character boundary
/// and " … (N more bytes)". Newlines are kept (a SpecError holds one problem per line): each line
/// is capped on its own.
std::string cap_message_line(std::string_view text, std::size_t max_bytes = kMaxMessageBytes);

}  // namespace armfarm

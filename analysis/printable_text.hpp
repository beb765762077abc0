#pragma once
// Names and values read from a database someone else made are shown, never obeyed: before they
// reach a terminal, a plot or a report they lose what could act on the reader's side (ANSI
// escape sequences, NUL, carriage returns that overwrite a line, bytes that are not UTF-8).
#include <string>

namespace armfarm {

/// `text` with every C0 control character (U+0000–U+001F), DEL (U+007F), C1 control (U+0080–U+009F)
/// and byte that is not part of well-formed UTF-8 replaced by U+FFFD, so that it prints as itself.
/// With `keep_newlines` a '\n' stays (a title with a second line); otherwise it is replaced too.
/// Printable UTF-8 (accents, arrows) is kept as it is.
std::string make_printable_text(const std::string& text, bool keep_newlines = false);

/// `text` for a page a reader looks at (the report's HTML): as make_printable_text, but a C0
/// control character or DEL shows as its Unicode control picture (ESC as U+241B "␛", CR as
/// U+240D "␍"), so that a name with an escape sequence reads as what it holds. Line breaks and
/// tabs stay (a spec in <pre>); C1 controls and bytes that are not UTF-8 become U+FFFD.
std::string make_visible_text(const std::string& text);

}  // namespace armfarm

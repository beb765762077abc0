#pragma once
// Strict reading of numbers in text input files (OBJ, CSV, DCG): a token is a number only if it
// is entirely one, in plain decimal notation, finite and in range; and error messages describe
// a bad token without echoing a file's words.
#include <optional>
#include <string>
#include <string_view>

namespace armfarm {

/// `token` as a finite double when it is, entirely, [+|-] digits [. digits] [(e|E) [+|-] digits]
/// (digits on at least one side of the point). Nullopt for anything else: empty, hex, inf, nan,
/// an embedded NUL, CR or other control character, a trailing letter, or a value that overflows
/// a double (1e999). Locale-independent.
std::optional<double> parse_finite_number(std::string_view token);

/// `token` as an int when it is, entirely, [+|-] digits within int's range; else nullopt.
std::optional<int> parse_integer(std::string_view token);

/// The end of an error message about a bad token: ": '1.2.3'" when it is at most 24 bytes of
/// characters a number can be made of (digits, sign, point, e, and the letters of inf and nan),
/// " (empty)", else " (a 31-byte token, not shown)" — so a message never quotes a file that is
/// not what it should be, such as a password file named as a CSV.
std::string describe_token(std::string_view token);

/// Why `token` is not a number parse_finite_number accepts, for "file:line: column 'q1': WHY":
/// "'1e-400' underflows to zero (below 4.9e-324, the smallest double, in magnitude)", "'1e999'
/// overflows a double", else "not a finite number" + describe_token(token).
std::string describe_bad_number(std::string_view token);

/// The end of "SUBJECT WHY" for a subject that names the value ("tag A: value 3", "vertex x"):
/// ": '1e-400' underflows to zero (…)" or ": '1e999' overflows a double (…)" for a decimal number
/// out of a double's range, else " is not a finite number" + describe_token(token).
std::string make_bad_number_ending(std::string_view token);

/// The first control character of `text` (bytes 0x00–0x1f and 0x7f, tab excepted) as its
/// position, or npos.
std::size_t find_control_character(std::string_view text);

/// "NUL", "CR", or "control character 0x1b": the byte at a position find_control_character found.
std::string describe_control_character(char c);

}  // namespace armfarm

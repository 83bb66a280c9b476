#pragma once
// Small helpers shared by the file readers and writers of mesohex_io.
#include <string>
#include <string_view>
#include <vector>

namespace mesohex {

// Largest input file a reader accepts, in bytes (just under 2^31: ids and line numbers are 32-bit ints, so no valid
// input is larger, and no line count can overflow).
inline constexpr std::size_t kMaxInputBytes = 2'000'000'000;

// The whole file as bytes, read in chunks, at most `max_bytes` of them: a larger file, or a device or pipe that never
// ends, is Error(IoError) "<path>: larger than <max_bytes> bytes" after reading max_bytes + 1 bytes, never more.
// Error(IoError) "<path>: cannot open for reading: <reason>" or "<path>: read error" otherwise.
std::string read_whole_file(const std::string& path, std::size_t max_bytes = kMaxInputBytes);

// Lower-case extension without the dot ("mesh", "obj"); "" when the file name has none.
std::string lower_extension(const std::string& path);

// Whitespace (space, tab, CR, FF, VT) separated tokens; the views point into `s`.
std::vector<std::string_view> split_whitespace(std::string_view s);
// The same into `out` (cleared first): a reader splitting line after line reuses one vector.
void split_whitespace(std::string_view s, std::vector<std::string_view>& out);

// Text from a file made safe to print inside an error message: at most `max_chars` characters of `s` (then "..."
// and the full length in bytes), every byte outside printable ASCII written as \xNN, a backslash as \\. A 20 MB
// line or a binary token never reaches the terminal whole or raw.
std::string quote_excerpt(std::string_view s, std::size_t max_chars = 80);

// True when `content` holds nothing but whitespace (space, tab, CR, LF, FF, VT).
bool is_blank_content(std::string_view content);

// Error(InvalidInput) "<path>:1: empty file (<expected>)" (never "line 0"), for a file of whitespace only.
[[noreturn]] void fail_empty_file(const std::string& path, const std::string& expected);

// Error(InvalidInput) "<path>:<line>: <what>" unless `count` items, each taking at least `min_bytes` bytes of the
// file, fit in `bytes_left` bytes: a header count must never make a reader reserve more than the file can hold.
void check_count_fits(const std::string& path, int line, long long count, std::size_t bytes_left, std::size_t min_bytes,
                      const std::string& what);

}  // namespace mesohex

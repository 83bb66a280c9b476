#pragma once
// Small helpers shared by the file readers and writers of mesohex_io.
#include <string>
#include <string_view>
#include <vector>

namespace mesohex {

// The whole file as bytes. Error(IoError) "<path>: cannot open for reading: <reason>" or "<path>: read error".
std::string read_whole_file(const std::string& path);

// Lower-case extension without the dot ("mesh", "obj"); "" when the file name has none.
std::string lower_extension(const std::string& path);

// Whitespace (space, tab, CR, FF, VT) separated tokens; the views point into `s`.
std::vector<std::string_view> split_whitespace(std::string_view s);

}  // namespace mesohex

#include "mesohex_io/text_input.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "mesohex/core/error.h"

namespace mesohex {

std::string read_whole_file(const std::string& path, std::size_t max_bytes) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw Error(ErrorCode::IoError, path + ": cannot open for reading: " + std::strerror(errno));
    std::error_code ec;
    const std::uintmax_t size = std::filesystem::file_size(path, ec);  // a hint only: devices and pipes have none
    std::string out;
    if (!ec) out.reserve(static_cast<std::size_t>(std::min<std::uintmax_t>(size, max_bytes)));
    constexpr std::size_t kChunk = std::size_t{1} << 20;  // bytes read per call
    std::size_t used = 0;
    while (true) {
        const std::size_t want = std::min(kChunk, max_bytes + 1 - used);
        out.resize(used + want);
        in.read(out.data() + used, static_cast<std::streamsize>(want));
        used += static_cast<std::size_t>(in.gcount());
        if (in.bad()) throw Error(ErrorCode::IoError, path + ": read error");
        if (used > max_bytes)
            throw Error(ErrorCode::IoError, path + ": larger than " + std::to_string(max_bytes) +
                                                " bytes: not a mesohex input (or a device that never ends)");
        if (!in) break;  // end of file
    }
    out.resize(used);
    return out;
}

std::string lower_extension(const std::string& path) {
    const std::size_t slash = path.find_last_of("/\\");
    const std::size_t dot = path.find_last_of('.');
    if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return {};
    std::string ext = path.substr(dot + 1);
    for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return ext;
}

namespace {
bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v'; }
}  // namespace

std::vector<std::string_view> split_whitespace(std::string_view s) {
    std::vector<std::string_view> out;
    split_whitespace(s, out);
    return out;
}

void split_whitespace(std::string_view s, std::vector<std::string_view>& out) {
    out.clear();
    std::size_t i = 0;
    while (i < s.size()) {
        while (i < s.size() && is_space(s[i])) ++i;
        const std::size_t b = i;
        while (i < s.size() && !is_space(s[i])) ++i;
        if (i > b) out.push_back(s.substr(b, i - b));
    }
}

std::string quote_excerpt(std::string_view s, std::size_t max_chars) {
    static const char* const hex = "0123456789abcdef";
    std::string out;
    const std::size_t n = std::min(s.size(), max_chars);
    out.reserve(n + 32);
    for (std::size_t i = 0; i < n; ++i) {
        const unsigned char c = static_cast<unsigned char>(s[i]);
        if (c == '\\') {
            out += "\\\\";
        } else if (c >= 0x20 && c < 0x7f) {
            out += static_cast<char>(c);
        } else {
            out += "\\x";
            out += hex[c >> 4];
            out += hex[c & 15];
        }
    }
    if (s.size() > n) out += "... (" + std::to_string(s.size()) + " bytes)";
    return out;
}

bool is_blank_content(std::string_view content) {
    for (const char c : content)
        if (!is_space(c) && c != '\n') return false;
    return true;
}

void fail_empty_file(const std::string& path, const std::string& expected) {
    throw Error(ErrorCode::InvalidInput, path + ":1: empty file (" + expected + ")", {ElementRef::Kind::FileLine, 1});
}

void check_count_fits(const std::string& path, int line, long long count, std::size_t bytes_left, std::size_t min_bytes,
                      const std::string& what) {
    const std::size_t per = std::max<std::size_t>(min_bytes, 1);
    if (count < 0 || static_cast<unsigned long long>(count) > bytes_left / per)
        throw Error(ErrorCode::InvalidInput,
                    path + ":" + std::to_string(line) + ": " + what + " " + std::to_string(count) +
                        " is more than the rest of the file (" + std::to_string(bytes_left) +
                        " bytes) can hold: truncated or corrupt file?",
                    {ElementRef::Kind::FileLine, line});
}

}  // namespace mesohex

#pragma once
// Shared by the fuzz targets: every input is one format-selecting byte followed by the file's content, parsed in
// memory by the readers' text forms (read_*_text): no file is written.
#include <cstddef>
#include <cstdint>
#include <initializer_list>
#include <string_view>

namespace mesohex::fuzz {

// One fuzz input: `format` = formats[data[0] % n] (an extension without the dot), `text` = data[1..size).
struct Input {
    std::string_view format;
    std::string_view text;
};

// Splits data[0..size) as described above; false (nothing to run) when size == 0.
bool split_input(const std::uint8_t* data, std::size_t size, std::initializer_list<std::string_view> formats,
                 Input& out);

// The name the readers give the input in their messages.
inline constexpr std::string_view kInputName = "fuzz-input";

}  // namespace mesohex::fuzz

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size);

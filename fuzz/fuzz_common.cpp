#include "fuzz_common.h"

namespace mesohex::fuzz {

bool split_input(const std::uint8_t* data, std::size_t size, std::initializer_list<std::string_view> formats,
                 Input& out) {
    if (size == 0 || formats.size() == 0) return false;
    out.format = formats.begin()[static_cast<std::size_t>(data[0]) % formats.size()];
    out.text = std::string_view(reinterpret_cast<const char*>(data + 1), size - 1);
    return true;
}

}  // namespace mesohex::fuzz

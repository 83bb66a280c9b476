#pragma once
// Shared by the fuzz targets: the readers take paths, so each input is written to a per-process temporary file
// whose extension the first byte selects (the rest is the file's content).
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace mesohex::fuzz {

// Writes data[1..size) to "<tmp>/mesohex_fuzz_<pid>.<ext>", ext = extensions[data[0] % n]; returns the path ("" when
// size == 0). The file is overwritten by the next input.
std::string write_input(const std::uint8_t* data, std::size_t size, const std::vector<std::string>& extensions);

}  // namespace mesohex::fuzz

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size);

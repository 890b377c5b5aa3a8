#pragma once
// PNG files of the window (screenshots, recorded frames), written atomically, each marked as
// the view's (a tEXt chunk "Software: millwear view" right after the image header), so that a
// screenshot replaces only a PNG the view wrote (own_files.hpp).
#include <cstdint>
#include <string>
#include <vector>

#include "view/own_files.hpp"

namespace millwear::view {

// rgb: width x height x 3 bytes, top row first. Throws RunError when it cannot be written.
void write_png(const std::string& file, int width, int height, const std::vector<std::uint8_t>& rgb);

// Why a PNG may not be written to `file` ("" when it may): overwrite_refusal with write_png's mark.
std::string png_refusal(const std::string& file, const std::vector<RunInput>& inputs);

}  // namespace millwear::view

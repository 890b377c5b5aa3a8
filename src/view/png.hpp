#pragma once
// PNG files of the window (screenshots, recorded frames), written atomically.
#include <cstdint>
#include <string>
#include <vector>

namespace millwear::view {

// rgb: width x height x 3 bytes, top row first. Throws RunError when it cannot be written.
void write_png(const std::string& file, int width, int height, const std::vector<std::uint8_t>& rgb);

}  // namespace millwear::view

// PNG encoding by stb_image_write (Debian's libstb), into memory, then one atomic write.
#include "view/png.hpp"

#include <filesystem>

#include <stb_image_write.h>

#include "common/errors.hpp"
#include "io/atomic_write.hpp"

namespace millwear::view {

namespace {
void append(void* context, void* data, int size) {
  auto* out = static_cast<std::string*>(context);
  out->append(static_cast<const char*>(data), static_cast<std::size_t>(size));
}

// Where the mark goes: after the 8-byte signature and the image header (IHDR: 4 bytes of
// length, 4 of type, 13 of data, 4 of CRC), the first chunk stb_image_write writes.
constexpr std::size_t kMarkAt = 8 + 25;

// The PNG chunk CRC (ISO 3309, as zlib's crc32) of a chunk's type and data.
std::uint32_t chunk_crc(const std::string& bytes) {
  std::uint32_t c = 0xFFFFFFFFu;
  for (const char ch : bytes) {
    c ^= static_cast<unsigned char>(ch);
    for (int k = 0; k < 8; ++k) c = (c >> 1) ^ (0xEDB88320u & (0u - (c & 1u)));
  }
  return c ^ 0xFFFFFFFFu;
}

std::string big_endian(std::uint32_t v) {
  return {static_cast<char>(v >> 24), static_cast<char>((v >> 16) & 0xFF), static_cast<char>((v >> 8) & 0xFF),
          static_cast<char>(v & 0xFF)};
}

// The tEXt chunk that marks the view's PNGs (readers skip it: it is ancillary).
const std::string& mark_chunk() {
  static const std::string chunk = [] {
    const std::string body = std::string("tEXt") + "Software" + '\0' + "millwear view";
    return big_endian(static_cast<std::uint32_t>(body.size() - 4)) + body + big_endian(chunk_crc(body));
  }();
  return chunk;
}
}  // namespace

void write_png(const std::string& file, int width, int height, const std::vector<std::uint8_t>& rgb) {
  if (width <= 0 || height <= 0 || rgb.size() != static_cast<std::size_t>(width) * height * 3)
    throw RunError("screenshot of " + file + ": no image to write");
  std::string bytes;
  if (!stbi_write_png_to_func(append, &bytes, width, height, 3, rgb.data(), width * 3) || bytes.size() < kMarkAt ||
      bytes.compare(kMarkAt - 21, 4, "IHDR") != 0)
    throw RunError("could not encode the PNG image " + file);
  bytes.insert(kMarkAt, mark_chunk());
  // Its folder made as a recording's is (a script's `screenshot shots/a.png`).
  const std::string folder = std::filesystem::path(file).parent_path().string();
  if (!folder.empty()) io::ensure_dir(folder);
  io::write_file_atomic(file, bytes);
}

std::string png_refusal(const std::string& file, const std::vector<RunInput>& inputs) {
  return overwrite_refusal(file, mark_chunk(), kMarkAt, "a PNG without its mark, the text \"Software: millwear view\"",
                           inputs);
}

}  // namespace millwear::view

#include "shaderfit/image/exr.hpp"

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfOutputFile.h>
#include <ImfStringAttribute.h>

#include <exception>

#include "shaderfit/core/error.hpp"

namespace shaderfit {

void write_exr(const std::string& path, std::size_t width, std::size_t height,
               std::span<const float> rgba,
               const std::vector<std::pair<std::string, std::string>>& attributes) {
  if (width == 0 || height == 0) throw Error("an EXR image needs a size of at least 1 x 1");
  if (rgba.size() != width * height * 4)
    throw Error("write_exr: wrong number of floats for the size");
  try {
    Imf::Header header(static_cast<int>(width), static_cast<int>(height));
    header.compression() = Imf::NO_COMPRESSION;
    for (const char* c : {"R", "G", "B", "A"})
      header.channels().insert(c, Imf::Channel(Imf::FLOAT));
    for (const auto& [name, value] : attributes) header.insert(name, Imf::StringAttribute(value));
    Imf::FrameBuffer fb;
    // The library only reads through these pointers.
    char* base = const_cast<char*>(reinterpret_cast<const char*>(rgba.data()));
    const std::size_t xs = 4 * sizeof(float), ys = xs * width;
    const char* names[] = {"R", "G", "B", "A"};
    for (int c = 0; c < 4; ++c)
      fb.insert(names[c], Imf::Slice(Imf::FLOAT, base + c * sizeof(float), xs, ys));
    Imf::OutputFile file(path.c_str(), header);
    file.setFrameBuffer(fb);
    file.writePixels(static_cast<int>(height));
  } catch (const std::exception& e) {
    throw Error("cannot write '" + path + "': " + e.what(), SourceLocation{path});
  }
}

}  // namespace shaderfit

#include "penumbra/render/exr_io.h"

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfIO.h>
#include <ImfInputFile.h>
#include <ImfOutputFile.h>

#include <algorithm>
#include <cstdint>
#include <exception>
#include <stdexcept>
#include <string>
#include <vector>

#include "penumbra/base/output_file.h"

namespace penumbra {
namespace {

// An OpenEXR output stream into memory.
class MemoryStream : public Imf::OStream {
 public:
  MemoryStream() : Imf::OStream("memory") {}
  void write(const char c[], int n) override {
    if (position_ + std::size_t(n) > bytes.size()) bytes.resize(position_ + std::size_t(n));
    std::copy(c, c + n, bytes.begin() + std::ptrdiff_t(position_));
    position_ += std::size_t(n);
  }
  std::uint64_t tellp() override { return position_; }
  void seekp(std::uint64_t position) override { position_ = std::size_t(position); }

  std::vector<char> bytes;

 private:
  std::size_t position_ = 0;
};

// One float plane per channel: OpenEXR reads and writes strided planes, and separate planes keep
// the stride arithmetic trivial.
struct Planes {
  std::vector<float> r, g, b;
  explicit Planes(std::size_t count) : r(count), g(count), b(count) {}
};

// OpenEXR addresses pixels through a base pointer shifted so that (dataWindow.min.x, .min.y) lands
// on element 0; the shifted pointer is only ever offset back into range by the library, but
// forming it with pointer arithmetic would be undefined, so it goes through an integer.
char* shiftedBase(float* data, const Imath::Box2i& window, int width) {
  const std::ptrdiff_t offset =
      -static_cast<std::ptrdiff_t>(window.min.x) -
      static_cast<std::ptrdiff_t>(window.min.y) * static_cast<std::ptrdiff_t>(width);
  return reinterpret_cast<char*>(reinterpret_cast<std::intptr_t>(data) +
                                 offset * static_cast<std::ptrdiff_t>(sizeof(float)));
}

Imf::FrameBuffer frameBufferFor(Planes& planes, const Imath::Box2i& window, int width) {
  const std::size_t xStride = sizeof(float);
  const std::size_t yStride = sizeof(float) * static_cast<std::size_t>(width);
  Imf::FrameBuffer frameBuffer;
  frameBuffer.insert("R", Imf::Slice(Imf::FLOAT, shiftedBase(planes.r.data(), window, width),
                                     xStride, yStride, 1, 1, 0.0));
  frameBuffer.insert("G", Imf::Slice(Imf::FLOAT, shiftedBase(planes.g.data(), window, width),
                                     xStride, yStride, 1, 1, 0.0));
  frameBuffer.insert("B", Imf::Slice(Imf::FLOAT, shiftedBase(planes.b.data(), window, width),
                                     xStride, yStride, 1, 1, 0.0));
  return frameBuffer;
}

}  // namespace

void writeExr(const Image& image, const std::filesystem::path& path) {
  if (image.width <= 0 || image.height <= 0) {
    throw std::runtime_error("cannot write EXR '" + path.string() + "': the image is empty");
  }
  const std::size_t count = image.pixels.size();
  Planes planes(count);
  for (std::size_t i = 0; i < count; ++i) {
    planes.r[i] = static_cast<float>(image.pixels[i].r);
    planes.g[i] = static_cast<float>(image.pixels[i].g);
    planes.b[i] = static_cast<float>(image.pixels[i].b);
  }
  // Encoded in memory, then written whole (base/output_file.h): OpenEXR's own file stream does
  // not report an error that only shows when the file is closed (a full disk).
  MemoryStream stream;
  try {
    Imf::Header header(image.width, image.height);
    header.compression() = Imf::ZIP_COMPRESSION;
    header.channels().insert("R", Imf::Channel(Imf::FLOAT));
    header.channels().insert("G", Imf::Channel(Imf::FLOAT));
    header.channels().insert("B", Imf::Channel(Imf::FLOAT));
    Imf::OutputFile file(stream, header);
    file.setFrameBuffer(frameBufferFor(planes, header.dataWindow(), image.width));
    file.writePixels(image.height);
  } catch (const std::exception& e) {
    throw std::runtime_error("cannot write EXR '" + path.string() + "': " + e.what());
  }
  writeOutputFile(path, [&](std::ostream& out) {
    out.write(stream.bytes.data(), std::streamsize(stream.bytes.size()));
  });
}

Image readExr(const std::filesystem::path& path) {
  try {
    Imf::InputFile file(path.c_str());
    const Imath::Box2i window = file.header().dataWindow();
    const int width = window.max.x - window.min.x + 1;
    const int height = window.max.y - window.min.y + 1;
    Image image(width, height);
    Planes planes(image.pixels.size());
    file.setFrameBuffer(frameBufferFor(planes, window, width));
    file.readPixels(window.min.y, window.max.y);
    for (std::size_t i = 0; i < image.pixels.size(); ++i) {
      image.pixels[i] = Rgb(planes.r[i], planes.g[i], planes.b[i]);
    }
    return image;
  } catch (const std::exception& e) {
    throw std::runtime_error("cannot read EXR '" + path.string() + "': " + e.what());
  }
}

}  // namespace penumbra

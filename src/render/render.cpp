// Software rasteriser for inspection pictures.
#include "foldfill/render.h"

#include <png.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>

#include "foldfill/error.h"
#include "foldfill/file.h"
#include "foldfill/vec3.h"

namespace foldfill {
namespace {

Vec3 normalized(const Vec3& a) {
  const double n = std::sqrt(dot(a, a));
  return n > 0 ? Vec3{a[0] / n, a[1] / n, a[2] / n} : Vec3{0, 0, 0};
}

// Orthonormal view basis: right, up, toward the viewer.
struct View {
  Vec3 right, up, back;
};

View view_of(const Camera& camera) {
  const double az = camera.azimuth_deg * M_PI / 180, el = camera.elevation_deg * M_PI / 180;
  const Vec3 back{std::cos(el) * std::sin(az), std::sin(el), std::cos(el) * std::cos(az)};
  const Vec3 right = normalized(cross({0, 1, 0}, back));
  return {right, cross(back, right), back};
}

}  // namespace

Camera frame(const std::vector<Vec3>& positions, const std::vector<Tri>& faces) {
  Vec3 lo{std::numeric_limits<double>::max(), std::numeric_limits<double>::max(),
          std::numeric_limits<double>::max()};
  Vec3 hi{-lo[0], -lo[1], -lo[2]};
  auto include = [&](const Vec3& p) {
    for (int k = 0; k < 3; ++k) {
      lo[k] = std::min(lo[k], p[k]);
      hi[k] = std::max(hi[k], p[k]);
    }
  };
  if (faces.empty()) {
    for (const Vec3& p : positions) include(p);
  } else {
    for (const Tri& f : faces) {
      for (int v : f) include(positions[v]);
    }
  }
  Camera camera;
  camera.target = {(lo[0] + hi[0]) / 2, (lo[1] + hi[1]) / 2, (lo[2] + hi[2]) / 2};
  camera.radius = 0.55 * std::sqrt(dot(sub(hi, lo), sub(hi, lo)));
  if (!(camera.radius > 0)) camera.radius = 1;
  return camera;
}

Image render(const Mesh& mesh, const Camera& camera, const RenderOptions& options) {
  Image image{options.width, options.height, {}};
  image.rgb.assign(static_cast<size_t>(image.width) * image.height * 3, 255);
  std::vector<double> depth(static_cast<size_t>(image.width) * image.height,
                            -std::numeric_limits<double>::infinity());
  const View view = view_of(camera);
  const double scale = 0.5 * std::min(image.width, image.height) / camera.radius;
  // Screen coordinates (pixels, y down) and depth (larger is nearer).
  std::vector<Vec3> screen(mesh.positions.size());
  for (size_t v = 0; v < screen.size(); ++v) {
    const Vec3 d = sub(mesh.positions[v], camera.target);
    screen[v] = {image.width / 2.0 + scale * dot(d, view.right),
                 image.height / 2.0 - scale * dot(d, view.up), dot(d, view.back)};
  }
  const Vec3 light = normalized({view.right[0] * 0.3 + view.up[0] * 0.5 + view.back[0],
                                 view.right[1] * 0.3 + view.up[1] * 0.5 + view.back[1],
                                 view.right[2] * 0.3 + view.up[2] * 0.5 + view.back[2]});
  for (int f = 0; f < mesh.face_count(); ++f) {
    const Tri& t = mesh.faces[f];
    const Vec3 &a = screen[t[0]], &b = screen[t[1]], &c = screen[t[2]];
    const double area = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
    if (std::abs(area) < 1e-12) continue;
    const Vec3 normal = normalized(cross(sub(mesh.positions[t[1]], mesh.positions[t[0]]),
                                         sub(mesh.positions[t[2]], mesh.positions[t[0]])));
    double lit = std::abs(dot(normal, light));
    if (options.shade_levels > 1) {
      lit = std::round(lit * (options.shade_levels - 1)) / (options.shade_levels - 1);
    }
    const double shade = 0.25 + 0.75 * lit;
    const bool highlighted = options.highlight_from >= 0 && f >= options.highlight_from;
    const double base[3] = {highlighted ? 240.0 : 200.0, highlighted ? 140.0 : 205.0,
                            highlighted ? 40.0 : 215.0};
    const int x0 = std::max(0, static_cast<int>(std::floor(std::min({a[0], b[0], c[0]}))));
    const int x1 =
        std::min(image.width - 1, static_cast<int>(std::ceil(std::max({a[0], b[0], c[0]}))));
    const int y0 = std::max(0, static_cast<int>(std::floor(std::min({a[1], b[1], c[1]}))));
    const int y1 =
        std::min(image.height - 1, static_cast<int>(std::ceil(std::max({a[1], b[1], c[1]}))));
    // Heights of the triangle over each edge, in pixels, to darken edges.
    const double edge_len[3] = {std::hypot(c[0] - b[0], c[1] - b[1]),
                                std::hypot(a[0] - c[0], a[1] - c[1]),
                                std::hypot(b[0] - a[0], b[1] - a[1])};
    for (int y = y0; y <= y1; ++y) {
      for (int x = x0; x <= x1; ++x) {
        const double px = x + 0.5, py = y + 0.5;
        const double w0 = ((b[0] - px) * (c[1] - py) - (b[1] - py) * (c[0] - px)) / area;
        const double w1 = ((c[0] - px) * (a[1] - py) - (c[1] - py) * (a[0] - px)) / area;
        const double w2 = 1 - w0 - w1;
        if (w0 < 0 || w1 < 0 || w2 < 0) continue;
        const double z = w0 * a[2] + w1 * b[2] + w2 * c[2];
        const size_t pixel = static_cast<size_t>(y) * image.width + x;
        if (z <= depth[pixel]) continue;
        depth[pixel] = z;
        const double distance_to_edge =
            std::min({w0 * std::abs(area) / edge_len[0], w1 * std::abs(area) / edge_len[1],
                      w2 * std::abs(area) / edge_len[2]});
        const double line = options.wireframe && distance_to_edge < 0.6 ? 0.7 : 1.0;
        for (int k = 0; k < 3; ++k) {
          image.rgb[3 * pixel + k] =
              static_cast<std::uint8_t>(std::clamp(base[k] * shade * line, 0.0, 255.0));
        }
      }
    }
  }
  return image;
}

namespace {

// Rows of a 5 x 7 glyph, top first; bit 4 is the leftmost pixel.
using Glyph = std::array<std::uint8_t, 7>;

Glyph glyph(char c) {
  static const Glyph letters[26] = {
      {0x0E, 0x11, 0x11, 0x1F, 0x11, 0x11, 0x11}, {0x1E, 0x11, 0x11, 0x1E, 0x11, 0x11, 0x1E},
      {0x0E, 0x11, 0x10, 0x10, 0x10, 0x11, 0x0E}, {0x1E, 0x11, 0x11, 0x11, 0x11, 0x11, 0x1E},
      {0x1F, 0x10, 0x10, 0x1E, 0x10, 0x10, 0x1F}, {0x1F, 0x10, 0x10, 0x1E, 0x10, 0x10, 0x10},
      {0x0E, 0x11, 0x10, 0x17, 0x11, 0x11, 0x0F}, {0x11, 0x11, 0x11, 0x1F, 0x11, 0x11, 0x11},
      {0x0E, 0x04, 0x04, 0x04, 0x04, 0x04, 0x0E}, {0x07, 0x02, 0x02, 0x02, 0x02, 0x12, 0x0C},
      {0x11, 0x12, 0x14, 0x18, 0x14, 0x12, 0x11}, {0x10, 0x10, 0x10, 0x10, 0x10, 0x10, 0x1F},
      {0x11, 0x1B, 0x15, 0x15, 0x11, 0x11, 0x11}, {0x11, 0x11, 0x19, 0x15, 0x13, 0x11, 0x11},
      {0x0E, 0x11, 0x11, 0x11, 0x11, 0x11, 0x0E}, {0x1E, 0x11, 0x11, 0x1E, 0x10, 0x10, 0x10},
      {0x0E, 0x11, 0x11, 0x11, 0x15, 0x12, 0x0D}, {0x1E, 0x11, 0x11, 0x1E, 0x14, 0x12, 0x11},
      {0x0F, 0x10, 0x10, 0x0E, 0x01, 0x01, 0x1E}, {0x1F, 0x04, 0x04, 0x04, 0x04, 0x04, 0x04},
      {0x11, 0x11, 0x11, 0x11, 0x11, 0x11, 0x0E}, {0x11, 0x11, 0x11, 0x11, 0x11, 0x0A, 0x04},
      {0x11, 0x11, 0x11, 0x15, 0x15, 0x15, 0x0A}, {0x11, 0x11, 0x0A, 0x04, 0x0A, 0x11, 0x11},
      {0x11, 0x11, 0x11, 0x0A, 0x04, 0x04, 0x04}, {0x1F, 0x01, 0x02, 0x04, 0x08, 0x10, 0x1F}};
  static const Glyph digits[10] = {
      {0x0E, 0x11, 0x13, 0x15, 0x19, 0x11, 0x0E}, {0x04, 0x0C, 0x04, 0x04, 0x04, 0x04, 0x0E},
      {0x0E, 0x11, 0x01, 0x02, 0x04, 0x08, 0x1F}, {0x1F, 0x02, 0x04, 0x02, 0x01, 0x11, 0x0E},
      {0x02, 0x06, 0x0A, 0x12, 0x1F, 0x02, 0x02}, {0x1F, 0x10, 0x1E, 0x01, 0x01, 0x11, 0x0E},
      {0x06, 0x08, 0x10, 0x1E, 0x11, 0x11, 0x0E}, {0x1F, 0x01, 0x02, 0x04, 0x08, 0x08, 0x08},
      {0x0E, 0x11, 0x11, 0x0E, 0x11, 0x11, 0x0E}, {0x0E, 0x11, 0x11, 0x0F, 0x01, 0x02, 0x0C}};
  if (c >= 'a' && c <= 'z') return letters[c - 'a'];
  if (c >= 'A' && c <= 'Z') return letters[c - 'A'];
  if (c >= '0' && c <= '9') return digits[c - '0'];
  switch (c) {
    case ' ':
      return {0, 0, 0, 0, 0, 0, 0};
    case '-':
      return {0, 0, 0, 0x1F, 0, 0, 0};
    case '.':
      return {0, 0, 0, 0, 0, 0x0C, 0x0C};
    case ':':
      return {0, 0x0C, 0x0C, 0, 0x0C, 0x0C, 0};
    case '_':
      return {0, 0, 0, 0, 0, 0, 0x1F};
    case '(':
      return {0x02, 0x04, 0x08, 0x08, 0x08, 0x04, 0x02};
    case ')':
      return {0x08, 0x04, 0x02, 0x02, 0x02, 0x04, 0x08};
  }
  return {0x0E, 0x11, 0x01, 0x02, 0x04, 0, 0x04};  // '?'
}

void fill_rect(Image& image, int x0, int y0, int x1, int y1, std::uint8_t grey) {
  for (int y = std::max(0, y0); y < std::min(image.height, y1); ++y)
    for (int x = std::max(0, x0); x < std::min(image.width, x1); ++x)
      for (int k = 0; k < 3; ++k)
        image.rgb[(static_cast<size_t>(y) * image.width + x) * 3 + k] = grey;
}

}  // namespace

void draw_label(Image& image, const std::string& text) {
  if (text.empty()) return;
  const int scale = 1 + image.height / 240;
  const int advance = 6 * scale;  // a glyph and a column of space
  const int margin = 2 * scale;
  const int width = static_cast<int>(text.size()) * advance - scale;
  fill_rect(image, margin, margin, 3 * margin + width, 3 * margin + 7 * scale, 255);
  for (size_t i = 0; i < text.size(); ++i) {
    const Glyph rows = glyph(text[i]);
    const int left = 2 * margin + static_cast<int>(i) * advance;
    for (int row = 0; row < 7; ++row)
      for (int column = 0; column < 5; ++column)
        if (rows[row] & (0x10 >> column))
          fill_rect(image, left + column * scale, 2 * margin + row * scale,
                    left + (column + 1) * scale, 2 * margin + (row + 1) * scale, 40);
  }
}

Image side_by_side(const std::vector<Image>& images) {
  Image out;
  for (const Image& image : images) {
    out.width += image.width;
    out.height = std::max(out.height, image.height);
  }
  out.rgb.assign(static_cast<size_t>(out.width) * out.height * 3, 255);
  int left = 0;
  for (const Image& image : images) {
    for (int y = 0; y < image.height; ++y) {
      std::copy_n(image.rgb.begin() + static_cast<size_t>(y) * image.width * 3, image.width * 3,
                  out.rgb.begin() + (static_cast<size_t>(y) * out.width + left) * 3);
    }
    left += image.width;
  }
  return out;
}

namespace {

// The image as palette indices with its palette (RGB triples, at most 256),
// or false when it has more colours than a palette holds.
bool to_palette(const Image& image, std::vector<std::uint8_t>& indices,
                std::vector<std::uint8_t>& palette) {
  std::vector<std::uint32_t> colours;
  const size_t pixels = image.rgb.size() / 3;
  std::vector<std::uint32_t> packed(pixels);
  for (size_t p = 0; p < pixels; ++p) {
    packed[p] = static_cast<std::uint32_t>(image.rgb[3 * p]) << 16 |
                static_cast<std::uint32_t>(image.rgb[3 * p + 1]) << 8 | image.rgb[3 * p + 2];
  }
  colours = packed;
  std::sort(colours.begin(), colours.end());
  colours.erase(std::unique(colours.begin(), colours.end()), colours.end());
  if (colours.size() > 256) return false;
  indices.resize(pixels);
  for (size_t p = 0; p < pixels; ++p) {
    indices[p] = static_cast<std::uint8_t>(
        std::lower_bound(colours.begin(), colours.end(), packed[p]) - colours.begin());
  }
  palette.clear();
  for (std::uint32_t c : colours) {
    palette.insert(palette.end(),
                   {static_cast<std::uint8_t>(c >> 16), static_cast<std::uint8_t>(c >> 8),
                    static_cast<std::uint8_t>(c)});
  }
  return true;
}

}  // namespace

void write_png(const Image& image, const std::string& path) {
  png_image png{};
  png.version = PNG_IMAGE_VERSION;
  png.width = static_cast<png_uint_32>(image.width);
  png.height = static_cast<png_uint_32>(image.height);
  png.format = PNG_FORMAT_RGB;
  // Few colours (flat renderings): an indexed PNG, about a third of the size.
  std::vector<std::uint8_t> indices, palette;
  const void* pixels = image.rgb.data();
  const void* colormap = nullptr;
  if (to_palette(image, indices, palette)) {
    png.format = PNG_FORMAT_RGB_COLORMAP;
    png.colormap_entries = static_cast<png_uint_32>(palette.size() / 3);
    pixels = indices.data();
    colormap = palette.data();
  }
  png_alloc_size_t size = 0;
  if (!png_image_write_get_memory_size(png, size, 0, pixels, 0, colormap)) {
    throw CannotWriteError(path + ": cannot encode PNG");
  }
  std::string bytes(size, '\0');
  if (!png_image_write_to_memory(&png, bytes.data(), &size, 0, pixels, 0, colormap)) {
    throw CannotWriteError(path + ": cannot encode PNG");
  }
  bytes.resize(size);
  write_file_atomically(path, bytes);
}

}  // namespace foldfill

// A small software renderer for looking at fills: shaded meshes, new faces
// highlighted, written as PNG. For inspection only; no GPU needed.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "foldfill/mesh.h"

namespace foldfill {

struct Image {
  int width = 0, height = 0;
  std::vector<std::uint8_t> rgb;  // row-major, top row first
};

struct Camera {
  Vec3 target{};      // looked-at point
  double radius = 1;  // half the visible extent
  double azimuth_deg = 30;
  double elevation_deg = 30;
};

// A camera that frames the bounding box of `positions` (or of the vertices
// of `faces` when it is non-empty).
Camera frame(const std::vector<Vec3>& positions, const std::vector<Tri>& faces = {});

struct RenderOptions {
  int width = 640, height = 480;
  int highlight_from = -1;  // faces with index >= this are drawn in orange (-1: none)
  bool wireframe = true;    // darken triangle edges
  // > 0: the shading is rounded to this many levels, so that the picture has
  // few colours and writes as a small indexed PNG (see write_png).
  int shade_levels = 0;
};

// Orthographic, z-buffered, two-sided Lambert shading.
Image render(const Mesh& mesh, const Camera& camera, const RenderOptions& options = {});

// Writes `text` into the top-left corner of `image`, dark on a white box, in
// a built-in 5 x 7 pixel font scaled with the image's height (a font pixel is
// 1 + height / 240 pixels wide and high): letters (as capitals),
// digits, space and - . : _ ( ); any other character is drawn as '?'. Text
// wider than the image is cut off.
void draw_label(Image& image, const std::string& text);

// Images next to each other, left to right (heights must match).
Image side_by_side(const std::vector<Image>& images);

// Writes an indexed PNG when the image has at most 256 colours, RGB
// otherwise. Throws CannotWriteError.
void write_png(const Image& image, const std::string& path);

}  // namespace foldfill

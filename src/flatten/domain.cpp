// Gluing the flat patch to the flattened strip (see domain.h).
#include "foldfill/domain.h"

#include <cmath>
#include <string>

#include "foldfill/error.h"

namespace foldfill {
namespace {

void check_parts_match(const Strip& strip, const Flattening& flat, const FlatPatch& patch) {
  const auto mismatch = [](const std::string& what) {
    return InternalError("make_embed_domain: " + what);
  };
  if (flat.uv.size() != strip.positions.size())
    throw mismatch("the flattening has " + std::to_string(flat.uv.size()) +
                   " vertices, the strip " + std::to_string(strip.positions.size()));
  if (patch.boundary_count != strip.loop_size)
    throw mismatch("the patch has " + std::to_string(patch.boundary_count) +
                   " boundary vertices, the hole loop " + std::to_string(strip.loop_size));
  if (strip.loop_size < 3) throw mismatch("the hole loop has fewer than 3 vertices");
  if (patch.uv.size() < static_cast<size_t>(patch.boundary_count))
    throw mismatch("the patch has fewer vertices than boundary vertices");
}

}  // namespace

EmbedDomain make_embed_domain(const Strip& strip, const Flattening& flat, const FlatPatch& patch) {
  check_parts_match(strip, flat, patch);
  EmbedDomain domain;
  domain.fixed_count = static_cast<int>(strip.positions.size());
  domain.loop_size = strip.loop_size;
  domain.strip_face_count = static_cast<int>(strip.faces.size());

  // Scale and origin from the loop, so every length option is relative to
  // the hole's own edge length.
  const int n = strip.loop_size;
  double loop_length = 0;
  Vec3 origin{0, 0, 0};
  Vec2 uv_centre{0, 0};
  for (int k = 0; k < n; ++k) {
    const Vec3& a = strip.positions[k];
    const Vec3& b = strip.positions[(k + 1) % n];
    loop_length += std::sqrt((b[0] - a[0]) * (b[0] - a[0]) + (b[1] - a[1]) * (b[1] - a[1]) +
                             (b[2] - a[2]) * (b[2] - a[2]));
    for (int d = 0; d < 3; ++d) origin[d] += a[d] / n;
    for (int d = 0; d < 2; ++d) uv_centre[d] += flat.uv[k][d] / n;
  }
  domain.origin = origin;
  domain.length_scale = loop_length / n;
  if (!(domain.length_scale > 0) || !std::isfinite(domain.length_scale))
    throw FillFailedError("make_embed_domain: the hole loop has zero length");
  const double inverse_scale = 1 / domain.length_scale;

  domain.fixed_positions.reserve(strip.positions.size());
  for (const Vec3& p : strip.positions) domain.fixed_positions.push_back(normalised(p, domain));

  // Strip vertices keep the flattening's uv; the patch's interior vertices
  // follow (its boundary vertices are the loop's, already there).
  const auto rest = [&](const Vec2& uv) {
    return Vec2{(uv[0] - uv_centre[0]) * inverse_scale, (uv[1] - uv_centre[1]) * inverse_scale};
  };
  domain.rest_uv.reserve(flat.uv.size() + patch.uv.size() - patch.boundary_count);
  for (const Vec2& uv : flat.uv) domain.rest_uv.push_back(rest(uv));
  for (size_t v = patch.boundary_count; v < patch.uv.size(); ++v)
    domain.rest_uv.push_back(rest(patch.uv[v]));

  domain.faces = strip.faces;
  const int interior_offset = domain.fixed_count - patch.boundary_count;
  for (const Tri& f : patch.faces) {
    Tri glued{};
    for (int k = 0; k < 3; ++k)
      glued[k] = f[k] < patch.boundary_count ? f[k] : f[k] + interior_offset;
    domain.faces.push_back(glued);
  }
  return domain;
}

}  // namespace foldfill

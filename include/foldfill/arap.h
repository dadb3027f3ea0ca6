// As-rigid-as-possible initialisation (Sorkine & Alexa 2007) of the patch with
// a shrunk rest shape, as in section 3.3 of Gisbert et al. 2023.
#pragma once

#include <vector>

#include "foldfill/domain.h"

namespace foldfill {

struct ArapOptions {
  double shrink = 0.5;  // c: the rest shape is the flat state scaled by c
  int iterations = 30;
};

// Returns positions (normalised, as in the domain) of all domain vertices;
// fixed vertices keep their positions. Starts from the flat patch mapped by
// the best-fitting similarity of the flat loop onto its 3D positions. The
// cotan system is factored once.
std::vector<Vec3> arap_embed(const EmbedDomain& domain, const ArapOptions& options = {});

}  // namespace foldfill

// Writes the seed corpus of the fuzz targets into OUTDIR: a coarse folded
// sheet with one hole, with texture coordinates from its flat layout, in every
// format and encoding (OBJ, PLY binary and ASCII, OFF, STL binary and ASCII).
#include <cstdio>
#include <exception>
#include <string>

#include "foldfill/examples.h"
#include "foldfill/io.h"

namespace {

foldfill::Mesh holed_sheet() {
  foldfill::FoldedSheetOptions options;
  options.width = 1;
  options.height = 1;
  options.edge_length = 0.2;
  options.amplitude = 0.1;
  options.folds = 1;
  const foldfill::CutMesh cut =
      foldfill::cut_disk_hole(foldfill::make_folded_sheet(options), {0.5, 0.5}, 0.25);
  foldfill::Mesh mesh = cut.cut.mesh;
  mesh.texcoords = cut.cut.flat;
  mesh.face_texcoords = mesh.faces;
  return mesh;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: make_seeds OUTDIR\n");
    return 2;
  }
  try {
    const std::string dir = argv[1];
    const foldfill::Mesh mesh = holed_sheet();
    foldfill::write_mesh(mesh, dir + "/seed_sheet.obj");
    foldfill::write_mesh(mesh, dir + "/seed_sheet.off");
    for (bool binary : {true, false}) {
      const std::string name = dir + (binary ? "/seed_sheet_binary" : "/seed_sheet_ascii");
      foldfill::write_mesh(mesh, name + ".ply", {binary});
      foldfill::write_mesh(mesh, name + ".stl", {binary});
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "make_seeds: %s\n", e.what());
    return 1;
  }
  return 0;
}

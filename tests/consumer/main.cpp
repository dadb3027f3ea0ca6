// Fills the built-in example through the installed package: one call to
// foldfill::fill, and a typed error for a loop id that names nothing.
#include <foldfill/error.h>
#include <foldfill/examples.h>
#include <foldfill/fill.h>

#include <cstdio>

int main() {
  const foldfill::DevelopableMesh sheet = foldfill::make_folded_sheet();
  const foldfill::Mesh input = foldfill::cut_disk_hole(sheet, {2.6, 1.5}, 0.7).cut.mesh;
  const foldfill::FillOutput result = foldfill::fill(input);
  if (result.report.holes.size() != 1 || !result.report.holes[0].filled ||
      result.mesh.face_count() <= input.face_count() ||
      result.mesh.face_hole.size() != result.mesh.faces.size()) {
    std::fprintf(stderr, "consumer: the example's hole was not filled\n");
    return 1;
  }
  foldfill::FillRequest request;
  request.selection.mode = foldfill::HoleSelection::Mode::Ids;
  request.selection.ids = {42};
  try {
    foldfill::fill(input, request);
    std::fprintf(stderr, "consumer: loop 42 was accepted\n");
    return 1;
  } catch (const foldfill::UsageError& e) {
    if (e.kind() != foldfill::ErrorKind::Usage) {
      std::fprintf(stderr, "consumer: a UsageError of kind %s\n", foldfill::to_string(e.kind()));
      return 1;
    }
  } catch (const foldfill::Error& e) {
    std::fprintf(stderr, "consumer: unexpected error: %s\n", e.what());
    return 1;
  }
  std::printf("consumer: filled loop %d with %d faces\n", result.report.holes[0].loop_id,
              result.report.holes[0].patch_face_count);
  return 0;
}

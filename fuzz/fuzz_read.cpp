// libFuzzer target for one mesh reader; the format is the compile definition
// FOLDFILL_FUZZ_FORMAT (Obj, Ply, Off or Stl), one executable per format.
#include <cstddef>
#include <cstdint>

#include "fuzz_entry.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  foldfill::fuzz::read_mesh_bytes({reinterpret_cast<const char*>(data), size},
                                  foldfill::MeshFormat::FOLDFILL_FUZZ_FORMAT);
  return 0;
}

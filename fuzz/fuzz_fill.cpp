// libFuzzer target for the whole fill on small OBJ meshes.
#include <cstddef>
#include <cstdint>
#include <cstdlib>

#include "fuzz_entry.h"

// One thread: libFuzzer measures one input at a time, and the fill's result
// does not depend on the thread count.
extern "C" int LLVMFuzzerInitialize(int*, char***) {
  setenv("OMP_NUM_THREADS", "1", 0);
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  foldfill::fuzz::fill_mesh_bytes({reinterpret_cast<const char*>(data), size});
  return 0;
}

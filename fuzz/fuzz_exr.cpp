// libFuzzer target: OpenEXR textures → render::read_image.
#include "fuzz_image.h"
extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) { return fuzz_read_image(data, size, ".exr"); }

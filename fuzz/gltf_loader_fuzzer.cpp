// libFuzzer target: the input is a whole .gltf or .glb file, given to the
// loader as it is. A LoadError (mbao::Error) or std::invalid_argument is the
// loader's answer to bad input; any other exception escaping, a crash, a
// sanitizer report, a hang or running out of memory is a finding.
#include <cstddef>
#include <cstdint>
#include <stdexcept>

#include "core/error.h"
#include "scene/gltf_loader.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    // External buffers and images are looked up beside the seed corpus, which
    // holds some. UV sets are read too: what a texture bake loads is all a
    // render loads and more.
    mbao::LoadOptions options;
    options.texcoords = true;
    mbao::load_gltf_from_memory(data, size, "fuzz-input", MBAO_FUZZ_BASE_DIR, options);
  } catch (const mbao::Error&) {
  } catch (const std::invalid_argument&) {
  }
  return 0;
}

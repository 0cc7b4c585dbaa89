// tinygltf's implementation, compiled from Debian's header (libtinygltf-dev)
// in place of Debian's libtinygltf.so, with the library's own switch
// TINYGLTF_NO_EXTERNAL_IMAGE: an image the file names by a URI keeps the URI
// and is never opened here, where the shared library reads every such image
// whole as it parses the file (SPEC 3.2: only the images whose alpha can cut
// a surface are opened, by GltfAlphaMasks). The sanitizer build compiles it
// instrumented like the rest, so that AddressSanitizer, UBSan and the
// fuzzer's coverage see into the parser that reads the untrusted bytes.
#define TINYGLTF_IMPLEMENTATION
#define TINYGLTF_NO_EXTERNAL_IMAGE
#include <tiny_gltf.h>

// tinygltf's implementation, compiled from Debian's header into the sanitizer
// build (sanitize/sanitizers.cmake) in place of the uninstrumented
// libtinygltf.so, so that AddressSanitizer, UBSan and the fuzzer's coverage
// see into the parser that reads the untrusted bytes.
#define TINYGLTF_IMPLEMENTATION
#include <tiny_gltf.h>

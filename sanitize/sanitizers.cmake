# The sanitizer build (MBAO_SANITIZE): every target compiled and linked with
# AddressSanitizer and UndefinedBehaviorSanitizer, any undefined behaviour
# fatal. Included by the top-level CMakeLists.txt before the targets are made,
# so the flags reach them all.
set(sanitizer_flags -fsanitize=address,undefined -fno-sanitize-recover=undefined -fno-omit-frame-pointer)
add_compile_options(${sanitizer_flags})
add_link_options(${sanitizer_flags})

# tinygltf from its header, instrumented like the rest (see tinygltf.cpp); the
# alias stands where find_package(TinyGLTF) would have put the shared library.
find_path(STB_IMAGE_DIR stb_image.h PATH_SUFFIXES stb REQUIRED)
find_library(STB_LIBRARY stb REQUIRED)
add_library(tinygltf_instrumented STATIC "${CMAKE_CURRENT_LIST_DIR}/tinygltf.cpp")
target_include_directories(tinygltf_instrumented PRIVATE "${STB_IMAGE_DIR}")
target_link_libraries(tinygltf_instrumented PRIVATE nlohmann_json::nlohmann_json "${STB_LIBRARY}")
add_library(TinyGLTF::TinyGLTF ALIAS tinygltf_instrumented)

# What every test of this build runs with (CTest's ENVIRONMENT): the
# LeakSanitizer suppressions for the uninstrumented OpenCL stack (lsan.supp
# says why), stack traces for UBSan's reports, and no tracking of dynamic TLS.
# Debian 12's sanitizer runtime (LLVM 14) takes a dynamic TLS block for glibc
# 2.19's layout whenever its address happens to sit at that header's offset in
# a page, and LeakSanitizer then scans a bogus range and dies at exit ("Tracer
# caught signal 11") after the test has passed (google/sanitizers#1322; runtimes
# up to LLVM 16 have it). PoCL dlopens a library per kernel build, so which test hits it
# shifts with the kernels (FirstLaunch, which builds every kernel afresh, did).
set(MBAO_SANITIZER_ENVIRONMENT
    "LSAN_OPTIONS=suppressions=${CMAKE_CURRENT_LIST_DIR}/lsan.supp:print_suppressions=0"
    "ASAN_OPTIONS=intercept_tls_get_addr=0"
    "UBSAN_OPTIONS=print_stacktrace=1")

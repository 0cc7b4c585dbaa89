# The sanitizer build (MBAO_SANITIZE): every target compiled and linked with
# AddressSanitizer and UndefinedBehaviorSanitizer, any undefined behaviour
# fatal. Included by the top-level CMakeLists.txt before the targets are made,
# so the flags reach them all.
set(sanitizer_flags -fsanitize=address,undefined -fno-sanitize-recover=undefined -fno-omit-frame-pointer)
add_compile_options(${sanitizer_flags})
add_link_options(${sanitizer_flags})

# The runtimes' options, compiled into each test and fuzzer binary (default_options.cpp says which and why).
add_library(mbao_sanitizer_options OBJECT "${CMAKE_CURRENT_LIST_DIR}/default_options.cpp")
target_compile_definitions(mbao_sanitizer_options PRIVATE MBAO_LSAN_SUPPRESSIONS="${CMAKE_CURRENT_LIST_DIR}/lsan.supp")

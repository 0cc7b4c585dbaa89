// The sanitizer runtimes' options for the binaries of the sanitizer build,
// compiled in: the runtimes read these before their environment variables, so
// they hold however a binary is started. (CTest's ENVIRONMENT, which carried
// them before, reached the discovered GoogleTest tests with its first variable
// only: gtest_discover_tests flattens a list-valued property.)
//
// LeakSanitizer: the suppressions for the uninstrumented OpenCL stack
// (lsan.supp says why). AddressSanitizer: no tracking of dynamic TLS. Debian
// 12's runtime (LLVM 14) takes a dynamic TLS block for glibc 2.19's layout
// whenever its address happens to sit at that header's offset in a page, and
// LeakSanitizer then scans a bogus range and dies at exit ("Tracer caught
// signal 11") after the test has passed (google/sanitizers#1322; runtimes up
// to LLVM 16 have it). PoCL dlopens a library per kernel build, so which test
// hits it shifts with the kernels. UBSan: stack traces in its reports.
extern "C" {
const char* __asan_default_options() { return "intercept_tls_get_addr=0"; }
const char* __lsan_default_options() { return "suppressions=" MBAO_LSAN_SUPPRESSIONS ":print_suppressions=0"; }
const char* __ubsan_default_options() { return "print_stacktrace=1"; }
}

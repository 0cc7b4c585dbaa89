// Portability layer for the headers shared by the C++ host and the OpenCL C kernels.
// Everything in kernels/mbao/ compiles as both; the host includes it as C++ and
// the runtime inlines it into the OpenCL sources.
#ifndef MBAO_PLATFORM_H
#define MBAO_PLATFORM_H

#ifdef __OPENCL_VERSION__
#define MBAO_FN static inline
#define MBAO_GLOBAL __global
typedef uint mbao_u32;
typedef ulong mbao_u64;
typedef uchar mbao_u8;
#define mbao_float_as_u32(x) as_uint(x)
#define mbao_u32_as_float(x) as_float(x)
#define mbao_floor(x) floor(x)
#define mbao_clz(x) clz(x)
#define mbao_popcount(x) popcount(x)
// A loop of constant count unrolled before PoCL builds its loops over work
// items, which it turns into vector code only where their bodies have no loops.
#define MBAO_UNROLL _Pragma("unroll")
#else
#include <cmath>
#include <cstdint>
#include <cstring>
#define MBAO_UNROLL
#define MBAO_FN inline
#define MBAO_GLOBAL
typedef std::uint32_t mbao_u32;
typedef std::uint64_t mbao_u64;
typedef std::uint8_t mbao_u8;
inline float mbao_floor(float x) { return std::floor(x); }
// Leading zero bits, 32 for zero as OpenCL's clz.
inline int mbao_clz(mbao_u32 x) { return x ? __builtin_clz(x) : 32; }
inline int mbao_popcount(mbao_u32 x) { return __builtin_popcount(x); }
inline mbao_u32 mbao_float_as_u32(float x) {
  mbao_u32 u;
  std::memcpy(&u, &x, sizeof u);
  return u;
}
inline float mbao_u32_as_float(mbao_u32 u) {
  float x;
  std::memcpy(&x, &u, sizeof x);
  return x;
}
#endif

#endif

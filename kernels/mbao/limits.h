// Limits the host checks and the kernels are sized for: one definition for both.
#ifndef MBAO_LIMITS_H
#define MBAO_LIMITS_H

// The branching estimator walks its tree depth first and keeps one surface per
// bounce in private memory; the path estimator keeps one, whatever b is.
#define MBAO_MAX_BRANCHING_BOUNCES 16

// The deepest kd-tree the builder makes: the full-stack traversal's stack
// holds this many entries (a power of two).
#define MBAO_KD_MAX_DEPTH 64

// Rays per work item walked together in the lanes of one vector (traversal
// "lanes": kd_lanes.h's rays each with a stack of its own, kd_packet.h's
// camera rays as one packet).
#define MBAO_LANES 16

// The denoiser's largest exponent on the normals' cosine (SPEC 7.3), and its
// bits: the filter raises to it by squaring over a fixed count of bits.
#define MBAO_MAX_NORMAL_EXPONENT 1024
#define MBAO_NORMAL_EXPONENT_BITS 11

#endif

"""Brute force in double precision: the oracle for rays aimed at edges and vertices.

The float oracle (oracle.py) decides hits by float edge functions, which near
an edge are rounding noise; mbao recomputes those in double. This one computes
the whole test in double from the float corners, for the same ray as mbao (the
same axes and the same float shear), so near an edge the two agree to double
precision, and a ray through an edge hits a triangle whose closed area it
really crosses. Written independently of mbao's kernels, like oracle.py.
"""

import pyopencl as cl

from oracle import BruteForce

_SOURCE = r"""
#pragma OPENCL EXTENSION cl_khr_fp64 : enable
#pragma OPENCL FP_CONTRACT OFF

double pick(double3 v, int k) { return k == 0 ? v.x : (k == 1 ? v.y : v.z); }
float pickf(float3 v, int k) { return k == 0 ? v.x : (k == 1 ? v.y : v.z); }

// Returns t of the hit with 0 < t <= t_max, or INFINITY.
float hit_distance(float3 of, float3 d, float3 p0, float3 p1, float3 p2, float t_max) {
    float3 a = fabs(d);
    int kz = (a.x > a.y) ? ((a.x > a.z) ? 0 : 2) : ((a.y > a.z) ? 1 : 2);
    int kx = (kz + 1) % 3, ky = (kz + 2) % 3;
    if (pickf(d, kz) < 0.0f) { int s = kx; kx = ky; ky = s; }
    // The ray's shear as a float, as the tracer has it; everything after in double.
    double sx = pickf(d, kx) / pickf(d, kz), sy = pickf(d, ky) / pickf(d, kz), sz = 1.0f / pickf(d, kz);
    double3 o = convert_double3(of);
    double3 A = convert_double3(p0) - o, B = convert_double3(p1) - o, C = convert_double3(p2) - o;
    double ax = pick(A, kx) - sx * pick(A, kz), ay = pick(A, ky) - sy * pick(A, kz);
    double bx = pick(B, kx) - sx * pick(B, kz), by = pick(B, ky) - sy * pick(B, kz);
    double cx = pick(C, kx) - sx * pick(C, kz), cy = pick(C, ky) - sy * pick(C, kz);
    double u = cx * by - cy * bx, v = ax * cy - ay * cx, w = bx * ay - by * ax;
    if ((u < 0.0 || v < 0.0 || w < 0.0) && (u > 0.0 || v > 0.0 || w > 0.0)) return INFINITY;
    double det = u + v + w;
    if (det == 0.0) return INFINITY;
    double t = (u * pick(A, kz) + v * pick(B, kz) + w * pick(C, kz)) * sz / det;
    return (t > 0.0 && t <= t_max) ? (float)t : INFINITY;
}

__kernel void closest(__global const float4* corners, uint triangles, __global const float4* origins,
                      __global const float4* directions, __global float* t_out, __global int* triangle_out) {
    const uint i = get_global_id(0);
    const float3 o = origins[i].xyz, d = directions[i].xyz;
    float best = INFINITY; int best_triangle = -1;
    for (uint k = 0; k < triangles; ++k) {
        float t = hit_distance(o, d, corners[3 * k].xyz, corners[3 * k + 1].xyz, corners[3 * k + 2].xyz, directions[i].w);
        if (t < best) { best = t; best_triangle = (int)k; }
    }
    t_out[i] = best;
    triangle_out[i] = best_triangle;
}

__kernel void distance_to(__global const float4* corners, __global const float4* origins,
                          __global const float4* directions, __global const int* triangle, __global float* t_out) {
    const uint i = get_global_id(0);
    const int k = triangle[i];
    t_out[i] = k < 0 ? INFINITY : hit_distance(origins[i].xyz, directions[i].xyz, corners[3 * k].xyz,
                                               corners[3 * k + 1].xyz, corners[3 * k + 2].xyz, directions[i].w);
}
"""


class ExactBruteForce(BruteForce):
    """BruteForce with every hit decided in double precision."""

    def __init__(self, vertices, indices, device):
        super().__init__(vertices, indices, device)
        self.program = cl.Program(self.context, _SOURCE).build()

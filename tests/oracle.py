"""Brute-force ray/triangle intersection with pyopencl: the traversal tests' oracle.

Written independently of mbao's kernels and host code: every ray is tested
against every triangle with the watertight test of Woop, Benthin and Wald
(JCGT 2013), so there is no acceleration structure to get wrong.
"""

import numpy as np
import pyopencl as cl

from mbao.devices import resolve

_PRAGMAS = r"""
#pragma OPENCL EXTENSION cl_khr_fp64 : enable
#pragma OPENCL FP_CONTRACT OFF
"""

_HIT_DISTANCE_IN_FLOAT = r"""
float pick(float3 v, int k) { return k == 0 ? v.x : (k == 1 ? v.y : v.z); }

// Returns t of the hit with 0 < t <= t_max, or INFINITY.
float hit_distance(float3 o, float3 d, float3 p0, float3 p1, float3 p2, float t_max) {
    float3 a = fabs(d);
    // The paper's "largest component" axis, ties broken toward the later axis.
    int kz = (a.x > a.y) ? ((a.x > a.z) ? 0 : 2) : ((a.y > a.z) ? 1 : 2);
    int kx = (kz + 1) % 3, ky = (kz + 2) % 3;
    if (pick(d, kz) < 0.0f) { int s = kx; kx = ky; ky = s; }
    float sx = pick(d, kx) / pick(d, kz), sy = pick(d, ky) / pick(d, kz), sz = 1.0f / pick(d, kz);
    float3 A = p0 - o, B = p1 - o, C = p2 - o;
    float ax = pick(A, kx) - sx * pick(A, kz), ay = pick(A, ky) - sy * pick(A, kz);
    float bx = pick(B, kx) - sx * pick(B, kz), by = pick(B, ky) - sy * pick(B, kz);
    float cx = pick(C, kx) - sx * pick(C, kz), cy = pick(C, ky) - sy * pick(C, kz);
    float u = cx * by - cy * bx, v = ax * cy - ay * cx, w = bx * ay - by * ax;
    if (u == 0.0f) u = (float)((double)cx * by - (double)cy * bx);
    if (v == 0.0f) v = (float)((double)ax * cy - (double)ay * cx);
    if (w == 0.0f) w = (float)((double)bx * ay - (double)by * ax);
    if ((u < 0.0f || v < 0.0f || w < 0.0f) && (u > 0.0f || v > 0.0f || w > 0.0f)) return INFINITY;
    float det = u + v + w;
    if (det == 0.0f) return INFINITY;
    float t = (u * sz * pick(A, kz) + v * sz * pick(B, kz) + w * sz * pick(C, kz)) / det;
    return (t > 0.0f && t <= t_max) ? t : INFINITY;
}
"""

# The brute force itself, for any hit_distance.
_KERNELS = r"""
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

// t of ray i against the one triangle asked about, INFINITY if it misses.
__kernel void distance_to(__global const float4* corners, __global const float4* origins,
                          __global const float4* directions, __global const int* triangle, __global float* t_out) {
    const uint i = get_global_id(0);
    const int k = triangle[i];
    t_out[i] = k < 0 ? INFINITY : hit_distance(origins[i].xyz, directions[i].xyz, corners[3 * k].xyz,
                                               corners[3 * k + 1].xyz, corners[3 * k + 2].xyz, directions[i].w);
}
"""


def pyopencl_device(device):
    """The pyopencl.Device that is the given mbao.Device."""
    for platform in cl.get_platforms():
        for candidate in platform.get_devices():
            if resolve(candidate) == device:
                return candidate
    raise LookupError(f"pyopencl does not see {device}")


class BruteForce:
    # OpenCL C defining float hit_distance(o, d, p0, p1, p2, t_max): t in (0, t_max], or INFINITY.
    hit_distance = _HIT_DISTANCE_IN_FLOAT

    def __init__(self, vertices, indices, device):
        self.context = cl.Context([pyopencl_device(device)])
        self.queue = cl.CommandQueue(self.context)
        self.program = cl.Program(self.context, _PRAGMAS + self.hit_distance + _KERNELS).build()
        corners = np.zeros((len(indices) * 3, 4), np.float32)
        corners[:, :3] = np.asarray(vertices, np.float32)[np.asarray(indices).ravel()]
        # A triangle of zero area is never hit (its corners as float32, exactly in float64).
        p = corners[:, :3].astype(np.float64).reshape(-1, 3, 3)
        flat = ~np.any(np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]), axis=1)
        corners.reshape(-1, 3, 4)[flat] = np.nan  # NaN fails every comparison: a miss
        self.triangle_count = len(indices)
        self.corners = cl.Buffer(self.context, cl.mem_flags.READ_ONLY | cl.mem_flags.COPY_HOST_PTR, hostbuf=corners)

    def _rays(self, origins, directions, t_max):
        n = len(origins)
        o = np.zeros((n, 4), np.float32)
        o[:, :3] = origins
        d = np.zeros((n, 4), np.float32)
        d[:, :3] = directions
        d[:, 3] = t_max
        flags = cl.mem_flags.READ_ONLY | cl.mem_flags.COPY_HOST_PTR
        return n, cl.Buffer(self.context, flags, hostbuf=o), cl.Buffer(self.context, flags, hostbuf=d)

    def closest(self, origins, directions, t_max=np.inf):
        """(t, triangle) of the closest hit of each ray; ties go to the first triangle."""
        n, o, d = self._rays(origins, directions, t_max)
        t = np.empty(n, np.float32)
        triangle = np.empty(n, np.int32)
        t_buffer = cl.Buffer(self.context, cl.mem_flags.WRITE_ONLY, t.nbytes)
        triangle_buffer = cl.Buffer(self.context, cl.mem_flags.WRITE_ONLY, triangle.nbytes)
        self.program.closest(
            self.queue, (n,), None, self.corners, np.uint32(self.triangle_count), o, d, t_buffer, triangle_buffer
        )
        cl.enqueue_copy(self.queue, t, t_buffer)
        cl.enqueue_copy(self.queue, triangle, triangle_buffer)
        return t, triangle.astype(np.int64)

    def distance_to(self, origins, directions, triangles, t_max=np.inf):
        """t at which each ray hits the triangle named for it (inf: it misses it)."""
        n, o, d = self._rays(origins, directions, t_max)
        t = np.empty(n, np.float32)
        t_buffer = cl.Buffer(self.context, cl.mem_flags.WRITE_ONLY, t.nbytes)
        which = cl.Buffer(
            self.context, cl.mem_flags.READ_ONLY | cl.mem_flags.COPY_HOST_PTR, hostbuf=np.asarray(triangles, np.int32)
        )
        self.program.distance_to(self.queue, (n,), None, self.corners, o, d, which, t_buffer)
        cl.enqueue_copy(self.queue, t, t_buffer)
        return t

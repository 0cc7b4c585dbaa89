"""Brute force in double precision: the oracle for rays aimed at edges and vertices.

The float oracle (oracle.py) decides hits by float edge functions, which near
an edge are rounding noise; mbao recomputes those in double. This one computes
the whole test in double from the float corners, for the same ray as mbao (the
same axes and the same float shear), so near an edge the two agree to double
precision, and a ray through an edge hits a triangle whose closed area it
really crosses. Written independently of mbao's kernels, like oracle.py.
"""

from oracle import BruteForce

_HIT_DISTANCE_IN_DOUBLE = r"""
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
"""


class ExactBruteForce(BruteForce):
    """BruteForce with every hit decided in double precision."""

    hit_distance = _HIT_DISTANCE_IN_DOUBLE

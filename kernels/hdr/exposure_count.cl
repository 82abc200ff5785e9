// Saturated / zero counts of a raw frame (kernels/hdr/exposure_count.hpp): each work-item
// strides over the frame 4 pixels at a time (one vload of their 12 interleaved channels,
// explicit int4 vectors: about twice as fast on PoCL as one pixel per step), each work-group
// sums its items in local memory and writes one partial (4 counts); the host adds the
// partials. No atomics: the result is deterministic. GROUP_SIZE (a power of two) comes from
// the host as a -D option.
#ifndef GROUP_SIZE
#error "build with -DGROUP_SIZE=<power of two>"
#endif

__kernel __attribute__((reqd_work_group_size(GROUP_SIZE, 1, 1))) void exposure_count(
    __global const ushort* raw, int pixels, int black_level, int saturated_signal, int zero_signal,
    int near_saturated_signal, int near_zero_signal, __global uint4* partials) {
  __local uint4 sums[GROUP_SIZE];
  const int lid = get_local_id(0);
  // Vector comparisons give -1 for true: subtracting them counts.
  int4 saturated = 0, zero = 0, near_saturated = 0, near_zero = 0;
  const int quads = pixels / 4;
  for (int q = get_global_id(0); q < quads; q += get_global_size(0)) {
    const int8 a = convert_int8(vload8(0, raw + 12 * q));
    const int4 c = convert_int4(vload4(0, raw + 12 * q + 8));
    const int4 r = (int4)(a.s0, a.s3, a.s6, c.s1);
    const int4 g = (int4)(a.s1, a.s4, a.s7, c.s2);
    const int4 b = (int4)(a.s2, a.s5, c.s0, c.s3);
    // Any channel passes an upper test iff the highest does, a lower test iff the lowest.
    const int4 hi = max(r, max(g, b)) - black_level;
    const int4 lo = min(r, min(g, b)) - black_level;
    saturated -= hi >= saturated_signal;
    zero -= lo <= zero_signal;
    near_saturated -= hi >= near_saturated_signal;
    near_zero -= lo <= near_zero_signal;
  }
  uint4 n =
      (uint4)((uint)(saturated.s0 + saturated.s1 + saturated.s2 + saturated.s3),
              (uint)(zero.s0 + zero.s1 + zero.s2 + zero.s3),
              (uint)(near_saturated.s0 + near_saturated.s1 + near_saturated.s2 + near_saturated.s3),
              (uint)(near_zero.s0 + near_zero.s1 + near_zero.s2 + near_zero.s3));
  if (get_global_id(0) == 0) {  // the last pixels % 4 pixels
    for (int i = 4 * quads; i < pixels; ++i) {
      const int r = raw[3 * i], g = raw[3 * i + 1], b = raw[3 * i + 2];
      const int hi = max(r, max(g, b)) - black_level;
      const int lo = min(r, min(g, b)) - black_level;
      n += (uint4)(hi >= saturated_signal ? 1u : 0u, lo <= zero_signal ? 1u : 0u,
                   hi >= near_saturated_signal ? 1u : 0u, lo <= near_zero_signal ? 1u : 0u);
    }
  }
  sums[lid] = n;
  barrier(CLK_LOCAL_MEM_FENCE);
  for (int stride = GROUP_SIZE / 2; stride > 0; stride /= 2) {
    if (lid < stride) sums[lid] += sums[lid + stride];
    barrier(CLK_LOCAL_MEM_FENCE);
  }
  if (lid == 0) partials[get_group_id(0)] = sums[0];
}

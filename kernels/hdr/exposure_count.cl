// Saturated / zero counts of a raw frame (kernels/hdr/exposure_count.hpp): each work-item
// strides over the pixels, each work-group sums its items in local memory and writes one
// partial (4 counts); the host adds the partials. No atomics: the result is deterministic.
// GROUP_SIZE (a power of two) comes from the host as a -D option.
#ifndef GROUP_SIZE
#error "build with -DGROUP_SIZE=<power of two>"
#endif

__kernel __attribute__((reqd_work_group_size(GROUP_SIZE, 1, 1))) void exposure_count(
    __global const ushort* raw, int pixels, int black_level, int saturated_signal, int zero_signal,
    int near_saturated_signal, int near_zero_signal, __global uint4* partials) {
  __local uint4 sums[GROUP_SIZE];
  const int lid = get_local_id(0);
  uint4 n = (uint4)(0u);
  for (int i = get_global_id(0); i < pixels; i += get_global_size(0)) {
    const int r = raw[3 * i + 0], g = raw[3 * i + 1], b = raw[3 * i + 2];
    // Any channel passes an upper test iff the highest does, a lower test iff the lowest.
    const int hi = max(r, max(g, b)) - black_level;
    const int lo = min(r, min(g, b)) - black_level;
    n += (uint4)(hi >= saturated_signal ? 1u : 0u, lo <= zero_signal ? 1u : 0u,
                 hi >= near_saturated_signal ? 1u : 0u, lo <= near_zero_signal ? 1u : 0u);
  }
  sums[lid] = n;
  barrier(CLK_LOCAL_MEM_FENCE);
  for (int stride = GROUP_SIZE / 2; stride > 0; stride /= 2) {
    if (lid < stride) sums[lid] += sums[lid + stride];
    barrier(CLK_LOCAL_MEM_FENCE);
  }
  if (lid == 0) partials[get_group_id(0)] = sums[0];
}

// Box-averages a keyframe's radiance (n x 6n texels) to faces of m = n / factor texels, for
// the SH projection (docs/light-capture.md): 25 coefficients need nothing finer than 32 x 32
// faces, and a 128 px keyframe would cost 16 times the host's projection work. Observed and
// filled texels count alike (push-pull has run). Output alpha: 1.
__kernel void envmap_downsample(__global const float4* texels, int n, __global float4* out, int m,
                                int factor) {
  const int x = get_global_id(0), row = get_global_id(1);
  if (x >= m || row >= 6 * m) return;
  const int face = row / m, y = row - face * m;
  float3 sum = (float3)(0.0f);
  for (int j = 0; j < factor; ++j) {
    const __global float4* line = texels + ((face * n) + y * factor + j) * n + x * factor;
    for (int i = 0; i < factor; ++i) sum += line[i].xyz;
  }
  out[row * m + x] = (float4)(sum / (float)(factor * factor), 1.0f);
}

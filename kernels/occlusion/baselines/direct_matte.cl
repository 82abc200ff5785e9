// Direct occlusion matte (the thesis's Direct1/Direct2 baselines): a per-pixel depth test.
// UNKNOWN_VISIBLE (0 or 1, a -D option): the alpha of a pixel on the object whose real depth
// is unknown (0). Ties (real == virtual) count as visible, as in the CVF cost's depth test, and
// so do real surfaces within the sensor's noise in front (the tolerance: docs/occlusion.md
// "Right at contact").
#ifndef UNKNOWN_VISIBLE
#error "build with -DUNKNOWN_VISIBLE=0 (Direct1) or -DUNKNOWN_VISIBLE=1 (Direct2)"
#endif

__kernel void direct_matte(__global const ushort* real_depth_mm,
                           __global const float* virtual_depth_mm, __global float* alpha, int width,
                           int height, float tolerance_mm) {
  const int x = get_global_id(0);
  const int y = get_global_id(1);
  if (x >= width || y >= height) return;
  const int i = y * width + x;
  const float v = virtual_depth_mm[i];
  const ushort r = real_depth_mm[i];
  float a;
  if (!(v > 0.0f)) {
    a = 0.0f;  // no virtual object (NaN included)
  } else if (r == 0) {
    a = UNKNOWN_VISIBLE ? 1.0f : 0.0f;
  } else {
    // depth_tolerance_mm() of cvf_params.hpp (TOL_QUAD, TOL_Z0: -D options), statement by
    // statement as the reference.
    const float d = v - TOL_Z0;
    float q = d * d;
    q = TOL_QUAD * q;
    const float tolerance = tolerance_mm + q;
    const float limit = v - tolerance;
    a = (float)r >= limit ? 1.0f : 0.0f;
  }
  alpha[i] = a;
}

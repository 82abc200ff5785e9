// Seeds a new keyframe from another: same radiance, every texel unobserved (alpha 0), so the
// new keyframe's first observations replace the inherited values (thesis ch. 6).
__kernel void seed_keyframe(__global const float4* source, __global float4* target, int count) {
  const int i = get_global_id(0);
  if (i >= count) return;
  target[i] = (float4)(source[i].xyz, 0.0f);
}

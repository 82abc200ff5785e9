// The "Guided" baseline's input: (r, g, b) in [0, 1] and the category matte (behind 1,
// process 0.5, infront and off-object 0), packed for guided_filter.cl.
__kernel void guided_matte_pack(__global const uchar* rgb, __global const uchar* categories, int w,
                                int h, __global float4* packed) {
  const int x = get_global_id(0), y = get_global_id(1);
  if (x >= w || y >= h) return;
  const int i = y * w + x;
  const uchar c = categories[i];  // 0 ignore, 1 behind, 2 infront, 3 process
  const float m = c == 1 ? 1.0f : c == 3 ? 0.5f : 0.0f;
  packed[i] = (float4)((float)rgb[3 * i] / 255.0f, (float)rgb[3 * i + 1] / 255.0f,
                       (float)rgb[3 * i + 2] / 255.0f, m);
}

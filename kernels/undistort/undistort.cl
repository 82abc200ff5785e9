// The colour camera's undistortion remap (undistort_map.hpp), applied at upload. Colour:
// bilinear between the four source pixels around the mapped point, rounded half up; depth:
// the nearest source pixel (never a blend of two surfaces). Outside the frame: black colour,
// unknown depth (0). undistort_reference.cpp computes the same in the same order.
#pragma OPENCL FP_CONTRACT OFF

#define VALID_ABOVE -1.0e5f  // UndistortMap::kInvalid is -1e6

__kernel void undistort_rgb8(__global const uchar* src, __global uchar* dst,
                             __global const float2* map, int width, int height) {
  const int x = get_global_id(0), y = get_global_id(1);
  if (x >= width || y >= height) return;
  const int i = y * width + x;
  const float2 s = map[i];
  const float fx0 = floor(s.x), fy0 = floor(s.y);
  if (!(s.x > VALID_ABOVE && fx0 >= 0.0f && fy0 >= 0.0f && fx0 + 1.0f < (float)width &&
        fy0 + 1.0f < (float)height)) {
    vstore3((uchar3)(0), i, dst);
    return;
  }
  const int j = (int)fy0 * width + (int)fx0;
  const float ax = s.x - fx0, ay = s.y - fy0;
  const float3 a = convert_float3(vload3(j, src)), b = convert_float3(vload3(j + 1, src));
  const float3 c = convert_float3(vload3(j + width, src));
  const float3 d = convert_float3(vload3(j + width + 1, src));
  const float3 top = a + ax * (b - a), bottom = c + ax * (d - c);
  vstore3(convert_uchar3_sat_rtz(top + ay * (bottom - top) + 0.5f), i, dst);
}

__kernel void undistort_depth(__global const ushort* src, __global ushort* dst,
                              __global const float2* map, int width, int height) {
  const int x = get_global_id(0), y = get_global_id(1);
  if (x >= width || y >= height) return;
  const int i = y * width + x;
  const float2 s = map[i];
  const float nx = floor(s.x + 0.5f), ny = floor(s.y + 0.5f);
  const bool inside =
      s.x > VALID_ABOVE && nx >= 0.0f && ny >= 0.0f && nx < (float)width && ny < (float)height;
  dst[i] = inside ? src[(int)ny * width + (int)nx] : (ushort)0;
}

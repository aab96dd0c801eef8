// The surface around a pixel from the segment's raster depth (include after
// declaring `u_in` (colour) and `u_depth` (r32f linear depth), and with
// filter_common.glsl): a least-squares plane over the covered pixels within
// `radius` whose depth is within 5 % of the centre's (scan depth is noisy
// and splats are flat), giving a smooth surface point and its derivatives
// per pixel in the segment's object space (surface_point()).
struct SurfacePatch {
  bool valid;  // the pixel has depth
  vec3 P;      // surface point at the pixel centre
  vec3 dPdx;   // change of P one pixel to the right
  vec3 dPdy;   // change of P one pixel up
};

SurfacePatch fit_surface(ivec2 p, int radius) {
  SurfacePatch s;
  float dc = imageLoad(u_depth, p).r;
  s.valid = !isinf(dc) && dc > 0.0 && covered(imageLoad(u_in, p));
  if (!s.valid) return s;
  ivec2 size = imageSize(u_in);
  mat3 A = mat3(0.0);
  vec3 b = vec3(0.0);
  for (int dy = -radius; dy <= radius; ++dy)
    for (int dx = -radius; dx <= radius; ++dx) {
      ivec2 q = p + ivec2(dx, dy);
      if (!in_image(q, size) || !covered(imageLoad(u_in, q))) continue;
      float d = imageLoad(u_depth, q).r;
      if (isinf(d) || abs(d - dc) > 0.05 * dc) continue;
      vec3 h = vec3(float(dx), float(dy), 1.0);
      A += outerProduct(h, h);
      b += h * (d - dc);
    }
  // Depth plane d = dc + fit.z + fit.x dx + fit.y dy; too few samples or a
  // degenerate fit (a line of pixels) fall back to flat depth.
  vec3 fit = vec3(0.0);
  if (A[2][2] >= 4.0 && abs(determinant(A)) > 1e-3) fit = inverse(A) * b;
  vec2 pos = vec2(p + u_origin) + 0.5;  // frame pixel: tiles match the frame
  float d0 = dc + fit.z;
  s.P = surface_point(pos, d0);
  s.dPdx = surface_point(pos + vec2(1.0, 0.0), d0 + fit.x) - s.P;
  s.dPdy = surface_point(pos + vec2(0.0, 1.0), d0 + fit.y) - s.P;
  return s;
}

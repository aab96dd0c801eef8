// The brush_splats mark's brush (seed 004 eq. 1): a mixture of Gaussians
// on a 3 x 3 grid, evaluated per fragment (no texture images); shared by
// brush_splats.frag and brush_splats_tiled.frag.
uniform int u_gaussians;     // 1..9
uniform float u_amplitude;   // A
uniform float u_dev;         // spacing of the centres
uniform float u_lambda;      // shape exponent
uniform float u_sigma_x;
uniform float u_sigma_y;
uniform int u_layers;        // 1 or 2
uniform float u_layer_scale; // second layer: the grid shrunk about the centre
uniform float u_layer_angle; // ... and turned (radians)
uniform float u_layer_tint;  // ... and its colour toward white (> 0) or black (< 0)
uniform float u_cut;         // alpha below this is no coverage
uniform float u_surface_cut; // alpha from which a brush is the pixel's surface (the depth pass; kSurfaceCut)
uniform float u_reach;       // |q| beyond which a Gaussian adds less than u_cut / (A N) (skipped)

// |(x_theta - x0) / sx|, |(y_theta - y0) / sy| of eq. 1: uv relative to
// the centre c, turned by theta (cos cs, sin sn).
vec2 brush_q(vec2 uv, vec2 c, float cs, float sn) {
  vec2 d = uv - c;
  vec2 r = vec2(cs * d.x - sn * d.y, sn * d.x + cs * d.y);
  return abs(r) / vec2(u_sigma_x, u_sigma_y);
}

// The mixture of eq. 1: rows = ceil(N / 3) rows of up to three columns,
// dev apart, centred on the texture; column c turned by angles[c].
// Gaussians beyond u_reach add less than the cut allows to matter: they
// count as 0. Clamped to 1.
// The loops have constant bounds so that they unroll and each column's
// angle is read at a constant index: a software rasterizer runs fragments
// in lock-step lanes, and an index that varies per lane goes through
// memory (and a branch costs both of its sides anyway).
float brush_alpha(vec2 uv, vec3 cs, vec3 sn) {
  int rows = (u_gaussians + 2) / 3;
  float sum = 0.0;
  for (int row = 0; row < 3; ++row) {
    int cols = clamp(u_gaussians - row * 3, 0, 3);
    for (int col = 0; col < 3; ++col) {
      vec2 c = vec2(0.5 + (float(col) - 0.5 * float(cols - 1)) * u_dev, 0.5 + (float(row) - 0.5 * float(rows - 1)) * u_dev);
      vec2 q = brush_q(uv, c, cs[col], sn[col]);
      float g = exp(-0.5 * (pow(q.x, u_lambda) + pow(q.y, u_lambda)));
      if (col < cols && q.x <= u_reach && q.y <= u_reach) sum += g;
    }
  }
  return clamp(u_amplitude * sum, 0.0, 1.0);
}

// Exact window positions for GL marks drawn in tiles (cpp/render/
// exact_raster.h): a frame position on a 1/256 pixel grid, less the tile's
// origin, through a power-of-two viewport whose transform is then exact.
uniform ivec2 u_origin;        // the images' frame pixel (0, 0)
uniform float u_raster_center; // window position of NDC 0 (the viewport's half side less its margin)
uniform float u_raster_half;   // half the viewport's side (a power of two)

// The window position (in the images) a frame position is drawn at.
vec2 exact_window(vec2 frame_px) {
  precise vec2 win = round(frame_px * 256.0) / 256.0 - vec2(u_origin);
  return win;
}

// Clip coordinates (w = 1) of a window position from exact_window().
vec4 exact_clip(vec2 win, float z) {
  precise vec2 ndc = (win - u_raster_center) / u_raster_half;
  return vec4(ndc, z, 1.0);
}

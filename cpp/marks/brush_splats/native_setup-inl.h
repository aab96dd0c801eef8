// The brush_splats native kernels' splat setup (compiled once per SIMD
// target by native_kernels.cpp): brush_common.glsl's brush_splat() and
// brush_splats_tiled.vert, a vector of points at a time. (Highway's
// per-target include guard.)
#if defined(POINTNPR_BRUSH_NATIVE_SETUP_INL_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef POINTNPR_BRUSH_NATIVE_SETUP_INL_H_
#undef POINTNPR_BRUSH_NATIVE_SETUP_INL_H_
#else
#define POINTNPR_BRUSH_NATIVE_SETUP_INL_H_
#endif

#include "marks/brush_splats/native_brush-inl.h"

HWY_BEFORE_NAMESPACE();
namespace pointnpr::brush_native::HWY_NAMESPACE {

// A splat's box holds the pixels whose centre lies within kBoxMargin of
// its quad's corners' box on screen: the ray through a centre farther out
// cannot meet the quad (the uv test's rounding moves it by far less), and
// a box so tight lets most splats of a pixel or two be dropped before
// they are rasterized (an empty box: no pixel centre at all). The first
// centre at or past v - margin is ceil(v - 0.5 - margin) = -floor(kBoxLo
// - v); the last at or before v + margin is floor(v - kBoxHi).
constexpr float kBoxMargin = 1.0f / 16.0f;
constexpr float kBoxLo = 0.5f + kBoxMargin, kBoxHi = 0.5f - kBoxMargin;  // (exact)

// m * (x, y, z, 1), row r, as transform(): ((m0 x + m1 y) + m2 z) + m3.
HWY_INLINE VF Row4(const glm::mat4& m, int r, VF x, VF y, VF z) {
  const DF d;
  return hn::Add(hn::Add(hn::Add(hn::Mul(hn::Set(d, m[0][r]), x), hn::Mul(hn::Set(d, m[1][r]), y)),
                         hn::Mul(hn::Set(d, m[2][r]), z)),
                 hn::Set(d, m[3][r]));
}
// mat3(m) * (x, y, z), row r.
HWY_INLINE VF Row3(const glm::mat4& m, int r, VF x, VF y, VF z) {
  const DF d;
  return hn::Add(hn::Add(hn::Mul(hn::Set(d, m[0][r]), x), hn::Mul(hn::Set(d, m[1][r]), y)), hn::Mul(hn::Set(d, m[2][r]), z));
}
HWY_INLINE void Normalize(VF& x, VF& y, VF& z) {
  const VF length = hn::Sqrt(hn::Add(hn::Add(hn::Mul(x, x), hn::Mul(y, y)), hn::Mul(z, z)));
  x = hn::Div(x, length), y = hn::Div(y, length), z = hn::Div(z, length);
}
// One coordinate of center + (t a + b_axis b) diameter.
HWY_INLINE VF Corner(VF center, VF t, VF b_axis, VF a, VF b, VF diameter) {
  return hn::Add(center, hn::Mul(hn::Add(hn::Mul(t, a), hn::Mul(b_axis, b)), diameter));
}

// The splats of points index[0, n), n at most a vector's lanes (the rest
// repeat the last): false (an empty box) where nothing is drawn.
void SetUpLanes(const Chunk& c, const Settings& s, const uint32_t* index, int n, Splat* out) {
  const DF d;
  const DI di;
  alignas(32) float px[kMaxLanes], py[kMaxLanes], pz[kMaxLanes], fr[kMaxLanes], fs[kMaxLanes];
  alignas(32) float tx[kMaxLanes], ty[kMaxLanes], tz[kMaxLanes], bx[kMaxLanes], by[kMaxLanes], bz[kMaxLanes];
  PointFrame made[kMaxLanes];
  const PointFrame* f[kMaxLanes];
  for (int i = 0; i < int(hn::Lanes(d)); ++i) {
    const uint32_t j = index[std::min(i, n - 1)];
    const glm::vec3& q = c.positions[j];
    px[i] = q.x, py[i] = q.y, pz[i] = q.z;
    if (c.frames) {
      f[i] = &c.frames[j];
    } else {
      made[i] = point_frame(c.in, s, j);
      f[i] = &made[i];
    }
    fr[i] = f[i]->radius, fs[i] = f[i]->stretch;
    tx[i] = f[i]->t.x, ty[i] = f[i]->t.y, tz[i] = f[i]->t.z;
    bx[i] = f[i]->b.x, by[i] = f[i]->b.y, bz[i] = f[i]->b.z;
  }
  const VF x = hn::Load(d, px), y = hn::Load(d, py), z = hn::Load(d, pz);
  const VF cx = Row4(c.view, 0, x, y, z), cy = Row4(c.view, 1, x, y, z), cz = Row4(c.view, 2, x, y, z);
  const VF depth = hn::Neg(cz);
  MF ok = hn::And(hn::Ge(depth, hn::Set(d, s.near)), hn::Le(depth, hn::Set(d, s.far)));
  const VF per = s.ortho ? hn::Set(d, 1.0f) : hn::Max(hn::Set(d, 1e-20f), depth);
  const VF px_per_unit = hn::Div(hn::Set(d, s.px_per_unit), per);
  const VF zero = hn::Zero(d), one = hn::Set(d, 1.0f);
  // max_radius bounds the farthest the brush's visible part reaches from
  // its point (brush_support()), as brush_common.glsl's does.
  const VF stretch = hn::Load(d, fs);
  const VF along = hn::Mul(hn::Set(d, s.support_along), stretch);
  const VF reach = hn::Sqrt(hn::Add(hn::Mul(along, along), hn::Set(d, s.support_across2)));
  const VF radius = hn::Min(hn::Div(hn::Set(d, s.max_radius_px), hn::Mul(px_per_unit, reach)), hn::Load(d, fr));
  ok = hn::And(ok, hn::Gt(radius, zero));
  // The view's axes where there is no normal (t zero).
  const VF t0x = hn::Load(d, tx), t0y = hn::Load(d, ty), t0z = hn::Load(d, tz);
  const MF no_normal = hn::And(hn::And(hn::Eq(t0x, zero), hn::Eq(t0y, zero)), hn::Eq(t0z, zero));
  VF tvx = Row3(c.view, 0, t0x, t0y, t0z), tvy = Row3(c.view, 1, t0x, t0y, t0z), tvz = Row3(c.view, 2, t0x, t0y, t0z);
  Normalize(tvx, tvy, tvz);
  const VF b0x = hn::Load(d, bx), b0y = hn::Load(d, by), b0z = hn::Load(d, bz);
  VF bvx = Row3(c.view, 0, b0x, b0y, b0z), bvy = Row3(c.view, 1, b0x, b0y, b0z), bvz = Row3(c.view, 2, b0x, b0y, b0z);
  Normalize(bvx, bvy, bvz);
  tvx = hn::IfThenElse(no_normal, one, tvx), tvy = hn::IfThenElse(no_normal, zero, tvy);
  tvz = hn::IfThenElse(no_normal, zero, tvz);
  bvx = hn::IfThenElse(no_normal, zero, bvx), bvy = hn::IfThenElse(no_normal, one, bvy);
  bvz = hn::IfThenElse(no_normal, zero, bvz);
  // The whole splat beyond the near plane (the exact path draws no other).
  const VF reach_z = hn::Mul(hn::Add(hn::Mul(hn::Abs(tvz), stretch), hn::Abs(bvz)), radius);
  ok = hn::AndNot(hn::Lt(hn::Sub(depth, reach_z), hn::Set(d, s.near)), ok);
  // The quad's corners on screen (frame pixels) and their box.
  static constexpr float kCorner[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  const VF diameter = hn::Mul(hn::Set(d, 2.0f), radius), half = hn::Set(d, 0.5f);
  alignas(32) float wx[4][kMaxLanes], wy[4][kMaxLanes];
  VF min_x = hn::Set(d, kInf), min_y = hn::Set(d, kInf), max_x = hn::Set(d, -kInf), max_y = hn::Set(d, -kInf);
  for (int k = 0; k < 4; ++k) {
    const VF a = hn::Mul(hn::Set(d, kCorner[k][0] - 0.5f), stretch), b = hn::Set(d, kCorner[k][1] - 0.5f);
    const VF qx = Corner(cx, tvx, bvx, a, b, diameter), qy = Corner(cy, tvy, bvy, a, b, diameter);
    const VF qz = Corner(cz, tvz, bvz, a, b, diameter);
    const VF w = Row4(s.projection, 3, qx, qy, qz);
    const VF wxk = hn::Mul(hn::Add(hn::Mul(hn::Div(Row4(s.projection, 0, qx, qy, qz), w), half), half), hn::Set(d, s.frame.x));
    const VF wyk = hn::Mul(hn::Add(hn::Mul(hn::Div(Row4(s.projection, 1, qx, qy, qz), w), half), half), hn::Set(d, s.frame.y));
    hn::Store(wxk, d, wx[k]);
    hn::Store(wyk, d, wy[k]);
    min_x = hn::Min(wxk, min_x), max_x = hn::Max(wxk, max_x);
    min_y = hn::Min(wyk, min_y), max_y = hn::Max(wyk, max_y);
  }
  const VF lo_x = hn::Set(d, float(s.clip.min.x + s.origin.x) - 2.0f);
  const VF hi_x = hn::Set(d, float(s.clip.max.x + s.origin.x) + 2.0f);
  const VF lo_y = hn::Set(d, float(s.clip.min.y + s.origin.y) - 2.0f);
  const VF hi_y = hn::Set(d, float(s.clip.max.y + s.origin.y) + 2.0f);
  ok = hn::And(ok, hn::And(hn::Ge(max_x, lo_x), hn::Le(min_x, hi_x)));  // (also NaN)
  ok = hn::And(ok, hn::And(hn::Ge(max_y, lo_y), hn::Le(min_y, hi_y)));
  // Pixels whose centre lies in the box or within kBoxMargin of it (the
  // uv test decides), clamped to the clip (no int overflow).
  const VF box_lo = hn::Set(d, kBoxLo), box_hi = hn::Set(d, kBoxHi);
  const VI ox = hn::Set(di, s.origin.x), oy = hn::Set(di, s.origin.y), one_i = hn::Set(di, 1), zero_i = hn::Zero(di);
  alignas(32) int32_t lo[2][kMaxLanes], hi[2][kMaxLanes];
  hn::Store(hn::Sub(hn::Sub(zero_i, FloorInt(hn::Sub(box_lo, hn::Max(lo_x, min_x)))), ox), di, lo[0]);
  hn::Store(hn::Sub(hn::Sub(zero_i, FloorInt(hn::Sub(box_lo, hn::Max(lo_y, min_y)))), oy), di, lo[1]);
  hn::Store(hn::Sub(hn::Add(FloorInt(hn::Sub(hn::Min(hi_x, max_x), box_hi)), one_i), ox), di, hi[0]);
  hn::Store(hn::Sub(hn::Add(FloorInt(hn::Sub(hn::Min(hi_y, max_y), box_hi)), one_i), oy), di, hi[1]);
  const VF u_scale = hn::Mul(diameter, stretch);
  alignas(32) float o[15][kMaxLanes];
  hn::Store(cx, d, o[0]), hn::Store(cy, d, o[1]), hn::Store(cz, d, o[2]);
  hn::Store(hn::Div(tvx, u_scale), d, o[3]), hn::Store(hn::Div(tvy, u_scale), d, o[4]);
  hn::Store(hn::Div(tvz, u_scale), d, o[5]);
  hn::Store(hn::Div(bvx, diameter), d, o[6]), hn::Store(hn::Div(bvy, diameter), d, o[7]);
  hn::Store(hn::Div(bvz, diameter), d, o[8]);
  hn::Store(hn::Sub(hn::Mul(tvy, bvz), hn::Mul(bvy, tvz)), d, o[9]);  // cross(tv, bv)
  hn::Store(hn::Sub(hn::Mul(tvz, bvx), hn::Mul(bvz, tvx)), d, o[10]);
  hn::Store(hn::Sub(hn::Mul(tvx, bvy), hn::Mul(bvx, tvy)), d, o[11]);
  hn::Store(hn::Sub(depth, reach_z), d, o[12]), hn::Store(hn::Add(depth, reach_z), d, o[13]);
  hn::Store(hn::Max(hn::Mul(hn::Set(d, s.depth_tolerance), radius), hn::Set(d, c.noise_offset)), d, o[14]);
  const unsigned valid = MaskBits(ok);
  for (int i = 0; i < n; ++i) {
    Splat& sp = out[i];
    if (!(valid >> i & 1)) {
      sp.lo = sp.hi = glm::ivec2(0);
      continue;
    }
    sp.lo = {lo[0][i], lo[1][i]};
    sp.hi = {hi[0][i], hi[1][i]};
    sp.center = {o[0][i], o[1][i], o[2][i]};
    sp.u_axis = {o[3][i], o[4][i], o[5][i]};
    sp.v_axis = {o[6][i], o[7][i], o[8][i]};
    sp.normal = {o[9][i], o[10][i], o[11][i]};
    sp.depth_range = {o[12][i], o[13][i]};
    sp.offset = o[14][i];
    for (int k = 0; k < 4; ++k) sp.wx[k] = wx[k][i], sp.wy[k] = wy[k][i];
    sp.rgb = glm::vec3(c.colors.at(index[i]));
    sp.weight = c.weight ? c.weight[index[i]] : 1.0f;
    if (c.shading) sp.rgb = ::pointnpr::glsl::diffuse_shaded(sp.rgb, sp.normal, s.light_dir, s.shading_strength);
    sp.two = f[i]->two;
    std::copy(f[i]->cs, f[i]->cs + 3, sp.cs);
    std::copy(f[i]->sn, f[i]->sn + 3, sp.sn);
  }
}

// Kernels::set_up.
void SetUp(const Chunk& c, const Settings& s, uint32_t begin, uint32_t end, Splat* out) {
  const uint32_t lanes = uint32_t(hn::Lanes(DF()));
  for (uint32_t j = begin; j < end; j += lanes, out += lanes) {
    const int n = int(std::min(lanes, end - j));
    uint32_t index[kMaxLanes];
    for (int i = 0; i < n; ++i) index[i] = c.first + (c.order ? c.order[j + uint32_t(i)] : j + uint32_t(i));
    SetUpLanes(c, s, index, n, out);
  }
}

}  // namespace pointnpr::brush_native::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#endif  // per-target include guard

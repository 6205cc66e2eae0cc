// The per-pair rejection kernel (ssGearsPixel.cxx), included by
// ssGearsKernels.h inside each instruction set's namespace: no include guard.

// 1 / x to a few float ulps: the reciprocal estimate and one Newton step
// (a third of the cost of three divisions in RejectPairs), or the division
// itself where the estimate is out of range. The rejection's margins are
// 1e-4 of the terms, far above the error.
static inline VF Recip(VF x)
{
#if SS_GEARS_LANES == 16
  VF r;
  const __m512 e = _mm512_maskz_rcp14_ps(0xFFFF, reinterpret_cast<const __m512&>(x));
  __builtin_memcpy(&r, &e, sizeof(r));
#elif SS_GEARS_LANES == 8
  VF r;
  const __m256 e = _mm256_rcp_ps(reinterpret_cast<const __m256&>(x));
  __builtin_memcpy(&r, &e, sizeof(r));
#else
  return 1.0f / x;
#endif
#if SS_GEARS_LANES != 4
  r = r * (2.0f - x * r);
  // x r is 1 to a few ulps; not where the estimate under- or overflowed
  // (|x| beyond 2^126 or subnormal), or x is 0, infinite or NaN
  const VF t = Abs(x * r - 1.0f);
  if (LaneMask((VI)!(t < 1e-5f)))
  {
    return 1.0f / x;
  }
  return r;
#endif
}

// Pairs this pixel keeps, written to out (indices into the group); returns
// their count; box gets, per entry, the samples it may cover. out holds
// g.n + SS_GEARS_LANES entries, box's columns stride >= g.n + SS_GEARS_LANES
// floats, and keep's kSmallColumns columns (when not null) as many: whole
// vectors are written; the group's arrays hold SS_GEARS_LANES - 1 readable
// floats past n. A pair is rejected
// when, by more than the margins:
//  - all three vertices lie beyond the pixel's depth, or behind the light;
//  - all three lie between pixel and light and their projection onto the
//    light, seen from S, misses every light sample (outside the sample
//    extent, or between two sample rows or columns);
//  - (a finite light) the triangle straddles S's depth or the light's plane
//    and all three vertices lie outside one side plane of the pyramid from S
//    to the samples' extent: the pyramid holds every segment from S to a
//    sample, and the triangle lies wholly outside that half-space;
//  - S and every light sample lie on the same side of the triangle's plane
//    (for a closed piece, S in front of an outward face: the closed-mesh rule);
//  - all three vertices lie below the pixel's tangent plane.
static inline std::size_t RejectPairs(const GroupArrays& g, const PixelParams& p, std::uint32_t* out, float* box,
  std::size_t stride, float* const* keep, RejectCounts& counts)
{
  const VF zero = VF{} + 0.0f, one = zero + 1.0f;
  const float m = p.m;
  const float gnum = p.dir ? 1.0f : p.Sz;
  const float Sxo = p.dir ? 0.0f : p.Sx, Syo = p.dir ? 0.0f : p.Sy;
  const float bx = Sxo * p.kx + p.off, by = Syo * p.ky + p.off;
  const float ax = std::abs(Sxo * p.kx), ay = std::abs(Syo * p.ky);
  const float sig = p.px * p.sx + p.py * p.sy + p.pz * p.sz;
  const VI finite = (VI{} + (p.dir ? 0 : 1)) != 0;
  const VI proj = (VI{} + (p.project ? 1 : 0)) != 0;
  const VF last1 = zero + (p.last + 1.0f);
  const VUI fullRows = VUI{} + p.fullRows;
  VI lane;
  for (int q = 0; q < SS_GEARS_LANES; ++q)
  {
    lane[q] = q;
  }
  const std::size_t n = g.n;
  std::size_t c = 0;
  counts = RejectCounts();
  for (std::size_t i = 0; i < n; i += SS_GEARS_LANES)
  {
    const VF X0 = Load(g.x0 + i), Y0 = Load(g.y0 + i), Z0 = Load(g.z0 + i);
    const VF X1 = Load(g.x1 + i), Y1 = Load(g.y1 + i), Z1 = Load(g.z1 + i);
    const VF X2 = Load(g.x2 + i), Y2 = Load(g.y2 + i), Z2 = Load(g.z2 + i);
    const VF d0 = p.sz - Z0, d1 = p.sz - Z1, d2 = p.sz - Z2;
    const VF b0 = p.cz + Z0, b1 = p.cz + Z1, b2 = p.cz + Z2;
    const VI beyond = (d0 < -m) & (d1 < -m) & (d2 < -m);
    const VI behind = finite & (b0 < -m) & (b1 < -m) & (b2 < -m);
    const VI valid = proj & (d0 > m) & (d1 > m) & (d2 > m) & (~finite | ((b0 > m) & (b1 > m) & (b2 > m)));
    // the projection in sample-index units (only used where valid)
    const VF q0 = gnum * Recip(valid ? d0 : one), q1 = gnum * Recip(valid ? d1 : one);
    const VF q2 = gnum * Recip(valid ? d2 : one);
    const VF u0 = (X0 - p.sx) * q0 * p.kx, u1 = (X1 - p.sx) * q1 * p.kx, u2 = (X2 - p.sx) * q2 * p.kx;
    const VF v0 = (Y0 - p.sy) * q0 * p.ky, v1 = (Y1 - p.sy) * q1 * p.ky, v2 = (Y2 - p.sy) * q2 * p.ky;
    const VF umin = Min(Min(u0, u1), u2), umax = Max(Max(u0, u1), u2);
    const VF vmin = Min(Min(v0, v1), v2), vmax = Max(Max(v0, v1), v2);
    const VF qm = Max(Max(q0, q1), q2);
    // margins: float rounding relative to the terms, plus the coordinates' own
    const VF mu = 1e-4f * (Max(Abs(umin), Abs(umax)) + ax) + m * qm * p.kx + 1e-3f;
    const VF mv = 1e-4f * (Max(Abs(vmin), Abs(vmax)) + ay) + m * qm * p.ky + 1e-3f;
    // does [lo, hi] hold a sample index 0..last? Shifted by +1 and clamped
    // to [0, last + 2] so that truncation is floor.
    const VF lu = Min(Max(umin + bx - mu + 1.0f, zero), last1 + 1.0f);
    const VF hu = Min(Max(umax + bx + mu + 1.0f, zero), last1 + 1.0f);
    const VF lv = Min(Max(vmin + by - mv + 1.0f, zero), last1 + 1.0f);
    const VF hv = Min(Max(vmax + by + mv + 1.0f, zero), last1 + 1.0f);
    const VF flu = __builtin_convertvector(__builtin_convertvector(lu, VI), VF);
    const VF flv = __builtin_convertvector(__builtin_convertvector(lv, VI), VF);
    const VF cu = Max(flu + (flu < lu ? one : zero), one), cv = Max(flv + (flv < lv ? one : zero), one);
    const VF eu = Min(__builtin_convertvector(__builtin_convertvector(hu, VI), VF), last1);
    const VF ev = Min(__builtin_convertvector(__builtin_convertvector(hv, VI), VF), last1);
    VI missed = valid & ((eu < cu) | (ev < cv));
    // A straddling triangle (not projected): the pyramid's side planes. A
    // point B at depth d = Sz - z_B > 0 has the sample-index coordinate
    // t = (Bx - Sx) Sz kx / d + bx, so B lies beyond the plane through S and
    // the samples' edge t = c where f(B) = (Bx - Sx) Sz kx - (c - bx) d > 0.
    // f is linear in B: all three vertices beyond puts the whole triangle
    // beyond, whatever their depths. Margins: 1e-4 of the terms for the
    // rounding, the coordinates' margin m through each factor, and 1e-3 of a
    // sample times d.
    const VI straddle = finite & proj & ~valid & ~beyond & ~behind;
    VI outside = VI{} + 0;
    if (LaneMask(straddle))
    {
      const VF Xs[3] = { X0 - p.sx, X1 - p.sx, X2 - p.sx }, Ys[3] = { Y0 - p.sy, Y1 - p.sy, Y2 - p.sy };
      const VF ds[3] = { d0, d1, d2 };
      const float cxr = p.last - bx, cxl = -bx, cyr = p.last - by, cyl = -by;
      VI outR = straddle, outL = straddle, outU = straddle, outD = straddle;
      for (int v = 0; v < 3; ++v)
      {
        const VF nx = Xs[v] * (gnum * p.kx), ny = Ys[v] * (gnum * p.ky), ad = Abs(ds[v]);
        const VF mx = 1e-4f * Abs(nx) + m * p.kx * (2.0f * gnum + Abs(Xs[v]) + ad) + 1e-3f * ad;
        const VF my = 1e-4f * Abs(ny) + m * p.ky * (2.0f * gnum + Abs(Ys[v]) + ad) + 1e-3f * ad;
        outR &= nx - cxr * ds[v] > mx + std::abs(cxr) * (1e-4f * ad + 2.0f * m);
        outL &= nx - cxl * ds[v] < -(mx + std::abs(cxl) * (1e-4f * ad + 2.0f * m));
        outU &= ny - cyr * ds[v] > my + std::abs(cyr) * (1e-4f * ad + 2.0f * m);
        outD &= ny - cyl * ds[v] < -(my + std::abs(cyl) * (1e-4f * ad + 2.0f * m));
      }
      outside = outR | outL | outU | outD;
      missed |= outside;
    }
    // the triangle's plane: S and the light on one side
    const VF NX = Load(g.nx + i), NY = Load(g.ny + i), NZ = Load(g.nz + i), ND = Load(g.nd + i);
    const VF sigma = NX * p.sx + NY * p.sy + NZ * p.sz - ND;
    const VI oneSide = ((sigma > m) & (Load(g.front + i) > 0.5f)) | ((sigma < -m) & (Load(g.back + i) > 0.5f));
    // the pixel's horizon
    const VF t0 = p.px * X0 + p.py * Y0 + p.pz * Z0 - sig;
    const VF t1 = p.px * X1 + p.py * Y1 + p.pz * Z1 - sig;
    const VF t2 = p.px * X2 + p.py * Y2 + p.pz * Z2 - sig;
    const VI below = (t0 < -m) & (t1 < -m) & (t2 < -m);
    // the samples it may cover (projected: the box; else all), for the exact raster
    const VF full0 = zero, full1 = last1 - 1.0f;
    const VF bi0 = valid ? cu - 1.0f : full0, bi1 = valid ? eu - 1.0f : full1;
    const VF bj0 = valid ? cv - 1.0f : full0, bj1 = valid ? ev - 1.0f : full1;
    __builtin_memcpy(box + i, &bi0, sizeof(bi0));
    __builtin_memcpy(box + stride + i, &bi1, sizeof(bi1));
    __builtin_memcpy(box + 2 * stride + i, &bj0, sizeof(bj0));
    __builtin_memcpy(box + 3 * stride + i, &bj1, sizeof(bj1));
    // rows j0..j1 full already: the pair changes no bit (rows only gain
    // bits, so the raster's covered skip would drop it too)
    const VUI r0 = (VUI)__builtin_convertvector(bj0, VI), r1 = (VUI)__builtin_convertvector(Max(bj1, bj0), VI);
    const VUI span = ((VUI{} + 2u) << r1) - ((VUI{} + 1u) << r0);
    const VI covered = (VI)((span & fullRows) == span) & (VI{} + (p.fullRows ? -1 : 0));
    const VI k = ~(beyond | behind | missed | oneSide | below) & (lane + static_cast<int>(i) < VI{} + static_cast<int>(n));
    counts.covered += static_cast<std::size_t>(__builtin_popcount(LaneMask(k & covered)));
    // (the pyramid's own rejections: those no other test made)
    const VI inRange = lane + static_cast<int>(i) < VI{} + static_cast<int>(n);
    counts.outsidePyramid +=
      static_cast<std::size_t>(__builtin_popcount(LaneMask(outside & ~(oneSide | below) & inRange)));
    const VI kept = k & ~covered;
    const int nk = Compact(lane + static_cast<int>(i), kept, out + c);
    if (keep && nk > 0)
    {
      // the small-triangle test's inputs, in the order of kSmallColumns
      const VF col[kSmallColumns] = { X0, Y0, Z0, X1, Y1, Z1, X2, Y2, Z2, NX, NY, NZ, ND, bi0, bi1, bj0, bj1 };
      for (int q = 0; q < kSmallColumns; ++q)
      {
        Compact(col[q], kept, keep[q] + c);
      }
    }
    c += static_cast<std::size_t>(nk);
  }
  return c;
}

// The exact raster's filtered fast path for small triangles (ssGearsPixel.cxx),
// included by ssGearsKernels.h inside each instruction set's namespace: no
// include guard.
//
// SmallBits: for candidates whose box of samples is at most kSmallSide a side
// and that lie strictly between S and the light, not near S (the start rule),
// the bits the exact raster would set, from the triangle's projection onto
// the light plane in float: a sample is inside when every edge function of
// the projected triangle is positive beyond a bound on the float rounding,
// outside when one is negative beyond it. For a triangle between S and the
// light the projection holds exactly the samples whose segment from S crosses
// it, so a decided sample gets the raster's bit (whose own rounding is far
// below the bound); a candidate with any sample within the bound of an edge
// (ties included), or whose projection is too thin to orient, gets
// kUndecided and goes through the exact raster.
//
// The bound (stop 46; it was 1e-6 of the scene's extent R per coordinate,
// which the canopy's leaves crossed for a quarter of their candidates). Per
// coordinate c of a vertex, the kernel's X_c - s_c differs from the exact
// raster's B_c - S_c (double, light frame) by the roundings of fl(B_c) (the
// face's columns), of fl(o_c) and of their difference (ClusterFilter), and of
// s_c = fl(S_c - o_c) (MakePixelParams): with u = 2^-24 and |B_c| <= |X_c| +
// |o_c|, at most E_c = u (2 |X_c| + 2 |o_c| + |s_c|); twice that is taken,
// 2.4e-7 (|X_c| + |o_c|) + 1.2e-7 |s_c|. Through the projection
// du = (X - s_x) q k / W with q = gnum / d, d = s_z - Z: E_x moves du by
// q (k / W) E_x, and the depth's error E_z + u |d| changes q by that over d,
// moving du by |du| E_z / d (the term a bound from R alone left out: large
// for a vertex far to the side of S and close to it). The remaining roundings
// (q's division, the products, the offset bx) are relative, at most a few u
// of |du| + |bx|: 1e-6 (|du| + ax + 1). Per lane mu (mv) is the largest over
// the vertices, and an edge function E = du (sv - va) - dv (su - ua) over
// spans Wu, Wv errs by less than 3 (Wu mv + Wv mu) + 4 mu mv + 1e-6 Wu Wv
// (the edge function's own roundings are at most 8 u Wu Wv = 4.8e-7 Wu Wv, the
// review of stop 46 counted; the term was 4e-7 until then).
// The gates take the same roundings: a vertex counts as between S and the
// light when d > m + E_z (d errs by at most E_z / 2), and S as off the
// triangle's plane when |sigma| > nearEps + m + E_sigma, E_sigma = 7.2e-7
// (|s|_1 + |o|_1) + 3.6e-7 |X_0|_1: twice the roundings of the float unit
// normal (u per component, against |S| = |s + o|), of fl(S - o), fl(o), fl(n . B0)
// and the float dot products.
// (GEARSFiltered.WorstCaseRoundingNearTiesAtTheKernels builds such cases.)

// Lane q of the result is base[idx[q]] where mask is set, else 0 (32-bit
// lanes; the winding count's kernels use it).
static inline VI GatherI(const std::int32_t* base, VI idx, VI mask)
{
  // (masked forms: GCC 12's plain ones warn of an uninitialised operand)
#if SS_GEARS_LANES == 16
  const __m512i r = _mm512_mask_i32gather_epi32(_mm512_setzero_si512(),
    _mm512_movepi32_mask(reinterpret_cast<const __m512i&>(mask)), reinterpret_cast<const __m512i&>(idx), base, 4);
  VI v;
  __builtin_memcpy(&v, &r, sizeof(v));
  return v;
#elif SS_GEARS_LANES == 8
  const __m256i r = _mm256_mask_i32gather_epi32(_mm256_setzero_si256(), base, reinterpret_cast<const __m256i&>(idx),
    reinterpret_cast<const __m256i&>(mask), 4);
  VI v;
  __builtin_memcpy(&v, &r, sizeof(v));
  return v;
#else
  VI v;
  for (int q = 0; q < SS_GEARS_LANES; ++q)
  {
    std::int32_t x = 0;
    if (mask[q])
    {
      __builtin_memcpy(&x, base + idx[q], 4); // (bytes: base may hold floats)
    }
    v[q] = x;
  }
  return v;
#endif
}

// The largest lane of v.
static inline int HMax(VI v)
{
#if SS_GEARS_LANES >= 8
#if SS_GEARS_LANES == 16
  // (masked forms: GCC 12 warns of the plain ones' undefined operand)
  const __m512i w = reinterpret_cast<const __m512i&>(v);
  __m256i x = _mm256_max_epi32(_mm512_maskz_extracti64x4_epi64(0xF, w, 0), _mm512_maskz_extracti64x4_epi64(0xF, w, 1));
#else
  __m256i x = reinterpret_cast<const __m256i&>(v);
#endif
  x = _mm256_max_epi32(x, _mm256_permute2x128_si256(x, x, 1));
  x = _mm256_max_epi32(x, _mm256_shuffle_epi32(x, 0x4E));
  x = _mm256_max_epi32(x, _mm256_shuffle_epi32(x, 0xB1));
  return _mm256_cvtsi256_si32(x);
#else
  int r = v[0];
  for (int q = 1; q < SS_GEARS_LANES; ++q)
  {
    r = std::max(r, static_cast<int>(v[q]));
  }
  return r;
#endif
}

static inline void SmallBits(
  const float* const* in, const PixelParams& p, std::size_t n, std::uint32_t* out, std::size_t stride)
{
  VI lane;
  for (int q = 0; q < SS_GEARS_LANES; ++q)
  {
    lane[q] = q;
  }
  const VF zero = VF{} + 0.0f, one = zero + 1.0f;
  const float m = p.m;
  const float gnum = p.dir ? 1.0f : p.Sz;
  const float Sxo = p.dir ? 0.0f : p.Sx, Syo = p.dir ? 0.0f : p.Sy;
  const float bx = Sxo * p.kx + p.off, by = Syo * p.ky + p.off;
  const float ax = std::abs(Sxo * p.kx) + p.off, ay = std::abs(Syo * p.ky) + p.off;
  for (std::size_t i = 0; i < n; i += SS_GEARS_LANES)
  {
    // (the columns are padded: lanes past n load what lies there, and drop)
    const VI inRange = lane + static_cast<int>(i) < VI{} + static_cast<int>(n);
    const VF i0 = Load(in[13] + i), i1 = Load(in[14] + i), j0 = Load(in[15] + i), j1 = Load(in[16] + i);
    VI ok = inRange & (i1 - i0 < float(kSmallSide)) & (j1 - j0 < float(kSmallSide)) & (VI{} + (p.project ? -1 : 0));
    VUI out0 = VUI{} + kUndecided, rowsOut[kSmallSide];
    for (int r = 0; r < kSmallSide; ++r)
    {
      rowsOut[r] = VUI{} + 0u;
    }
    if (LaneMask(ok))
    {
      VF X[3], Y[3], Z[3];
      for (int v = 0; v < 3; ++v)
      {
        X[v] = Load(in[3 * v] + i);
        Y[v] = Load(in[3 * v + 1] + i);
        Z[v] = Load(in[3 * v + 2] + i);
      }
      // strictly between S and the light, S off the plane beyond the start
      // rule's reach: each beyond its own rounding too (a cell centre far
      // from S rounds d and sigma on a grid coarser than the margin; the
      // review of stop 46 found vertices just behind S passing d > m alone)
      const float esx = 1.2e-7f * std::abs(p.sx), esy = 1.2e-7f * std::abs(p.sy), esz = 1.2e-7f * std::abs(p.sz);
      VF d[3], ez[3];
      for (int v = 0; v < 3; ++v)
      {
        d[v] = p.sz - Z[v];
        ez[v] = 2.4e-7f * (Abs(Z[v]) + p.ao[2]) + esz; // E_z: d errs by at most half of it
        ok &= d[v] > m + ez[v];
        if (!p.dir)
        {
          ok &= p.cz + Z[v] > m;
        }
      }
      const VF sigma = Load(in[9] + i) * p.sx + Load(in[10] + i) * p.sy + Load(in[11] + i) * p.sz - Load(in[12] + i);
      const float so = std::abs(p.sx) + std::abs(p.sy) + std::abs(p.sz) + p.ao[0] + p.ao[1] + p.ao[2];
      const VF esig = 7.2e-7f * so + 3.6e-7f * (Abs(X[0]) + Abs(Y[0]) + Abs(Z[0]));
      ok &= Abs(sigma) > p.nearEps + m + esig;
      // projections in sample units and their rounding bounds (above)
      VF u[3], w[3], mu = zero, mv = zero, au = zero, av = zero;
      for (int v = 0; v < 3; ++v)
      {
        const VF dd = ok ? d[v] : one, q = gnum / dd;
        const VF du = (X[v] - p.sx) * q * p.kx, dv = (Y[v] - p.sy) * q * p.ky;
        u[v] = du + bx;
        w[v] = dv + by;
        const VF ex = 2.4e-7f * (Abs(X[v]) + p.ao[0]) + esx, ey = 2.4e-7f * (Abs(Y[v]) + p.ao[1]) + esy;
        const VF rz = ez[v] / dd;
        mu = Max(mu, q * p.kx * ex + Abs(du) * rz);
        mv = Max(mv, q * p.ky * ey + Abs(dv) * rz);
        au = Max(au, Abs(du));
        av = Max(av, Abs(dv));
      }
      mu += 1e-6f * (au + ax + 1.0f);
      mv += 1e-6f * (av + ay + 1.0f);
      const VF Wu = Max(Max(u[0], u[1]), u[2]) - Min(Min(u[0], u[1]), u[2]) + (i1 - i0) + 2.0f;
      const VF Wv = Max(Max(w[0], w[1]), w[2]) - Min(Min(w[0], w[1]), w[2]) + (j1 - j0) + 2.0f;
      const VF tol = 3.0f * (Wu * mv + Wv * mu) + 4.0f * mu * mv + 1e-6f * Wu * Wv;
      // orientation of the projected triangle
      const VF area = (u[1] - u[0]) * (w[2] - w[0]) - (w[1] - w[0]) * (u[2] - u[0]);
      ok &= Abs(area) > tol;
      if (LaneMask(ok))
      {
        const VF sgn = area > 0.0f ? one : zero - 1.0f;
        VF eu[3], ev[3];
        for (int e = 0; e < 3; ++e)
        {
          const int b = (e + 1) % 3;
          eu[e] = (u[b] - u[e]) * sgn;
          ev[e] = (w[b] - w[e]) * sgn;
        }
        // the largest box of the lanes still undecided
        const int rows = HMax(ok != 0 ? __builtin_convertvector(j1 - j0, VI) : VI{} - 1) + 1;
        const int cols = HMax(ok != 0 ? __builtin_convertvector(i1 - i0, VI) : VI{} - 1) + 1;
        // E = eu (sv - w) - ev (su - u), its two products once per row and
        // once per column (the same operations as at each sample: no fused
        // ones, so the same E); per column also its range test and the bit
        // it sets in its row (31 bounds the shift of columns past the box,
        // whose bits are never set)
        VF colTerm[3][kSmallSide];
        VUI colBit[kSmallSide];
        const VI ci = __builtin_convertvector(i0, VI);
        const VF inf = zero + __builtin_inff();
        for (int c = 0; c < cols; ++c)
        {
          const VF su = i0 + float(c);
          for (int e = 0; e < 3; ++e)
          {
            colTerm[e][c] = ev[e] * (su - u[e]);
          }
          // a column past the lane's box: E_0 = -inf there, so its samples
          // are outside (no bit, not undecided) without a range test
          colTerm[0][c] = su <= i1 ? colTerm[0][c] : inf;
          colBit[c] = (VUI{} + 1u) << (VUI)((ci + c) & 31);
        }
        VI undecided = VI{};
#if SS_GEARS_LANES == 16
        // (in mask registers: GCC turns the comparisons' masks into vectors)
        const __m512 tol16 = reinterpret_cast<const __m512&>(tol);
        __mmask16 undecided16 = 0;
#endif
        for (int r = 0; r < rows; ++r)
        {
          const VF sv = j0 + float(r);
          VF rowTerm[3];
          for (int e = 0; e < 3; ++e)
          {
            rowTerm[e] = eu[e] * (sv - w[e]);
          }
          rowTerm[0] = sv <= j1 ? rowTerm[0] : zero - inf; // (a row past the box: the same)
          VUI acc = VUI{} + 0u;
          for (int c = 0; c < cols; ++c)
          {
            // inside: every E above tol; outside: one below -tol; both from
            // the least E (finite on the lanes kept inside their box: their
            // area is; NaN, should it come, is undecided)
            const VF least = Min(Min(rowTerm[0] - colTerm[0][c], rowTerm[1] - colTerm[1][c]), rowTerm[2] - colTerm[2][c]);
#if SS_GEARS_LANES == 16
            const __m512 l = reinterpret_cast<const __m512&>(least);
            const __m512i a = reinterpret_cast<const __m512i&>(acc);
            const __m512i o = _mm512_mask_or_epi32(a, _mm512_cmp_ps_mask(l, tol16, _CMP_GT_OQ), a,
              reinterpret_cast<const __m512i&>(colBit[c]));
            __builtin_memcpy(&acc, &o, sizeof(acc));
            undecided16 |= _mm512_cmp_ps_mask(_mm512_abs_ps(l), tol16, _CMP_NGT_UQ);
#else
            undecided |= ~(Abs(least) > tol);
            acc |= (VUI)(least > tol) & colBit[c];
#endif
          }
          rowsOut[r] = acc;
        }
#if SS_GEARS_LANES == 16
        const __m512i u16 = _mm512_movm_epi32(undecided16);
        __builtin_memcpy(&undecided, &u16, sizeof(undecided));
#endif
        ok &= ~undecided;
        for (int r = 0; r < rows; ++r)
        {
          rowsOut[r] = ok != 0 ? rowsOut[r] : VUI{} + 0u;
        }
        out0 = ok != 0 ? (VUI)__builtin_convertvector(j0, VI) : VUI{} + kUndecided;
      }
    }
    // (whole vectors: out holds n rounded up to SS_GEARS_LANES per row)
    __builtin_memcpy(out + i, &out0, sizeof(out0));
    for (int r = 0; r < kSmallSide; ++r)
    {
      __builtin_memcpy(out + (1 + r) * stride + i, &rowsOut[r], sizeof(rowsOut[r]));
    }
  }
}

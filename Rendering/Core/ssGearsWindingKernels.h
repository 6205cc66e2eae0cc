// The winding count's kernels (ssGearsWinding.cxx), included by
// ssGearsKernels.h inside each instruction set's namespace: no include guard.
//
// WindingMembers: over the cell's list, the group's list (GroupFilter's
//   tests, fused: the group's list is never gathered) and of it the members,
//   the entries that lie strictly between every start point of the group and
//   the light and whose plane has every start point on one side (status 1:
//   in front, 2: behind), by more than the margin and the largest start
//   offset, with a neighbour in the cell's list (a triangle without one adds
//   three contour edges: the raster is cheaper); not slivers (front column
//   -1). Entries that hide no light sample from any start point of the group
//   (wholly beyond them, behind the light, or the plane test of RejectPairs
//   for every one: S and the light on one side, the closed-mesh rule) are
//   neither members nor in the rest.
// ContourEdges: the members' edges that do not cancel against a neighbour
//   member (the contour of the set), with their vertices.
// ContourPixel: of those, the edges that may step one pixel's count at a
//   sample: by the projected vertices in float with the rejection kernel's
//   margins, the edge spans a sample row and does not lie right of every
//   sample.

static inline void WindingMembers(const GroupArrays& g, const std::uint32_t* ids, MemberSplit& s)
{
  const float* const src[15] = { g.x0, g.y0, g.z0, g.x1, g.y1, g.z1, g.x2, g.y2, g.z2, g.nx, g.ny, g.nz, g.nd,
    g.front, g.back };
  const WindingBox& b = s.box;
  std::size_t nm = 0, nr = 0, kept = 0;
  int below = 0;
  VI lane;
  for (int q = 0; q < SS_GEARS_LANES; ++q)
  {
    lane[q] = q;
  }
  const float m = b.m;
  const float cx = 0.5f * (b.lo[0] + b.hi[0]), cy = 0.5f * (b.lo[1] + b.hi[1]), cz = 0.5f * (b.lo[2] + b.hi[2]);
  const float hx = 0.5f * (b.hi[0] - b.lo[0]), hy = 0.5f * (b.hi[1] - b.lo[1]), hz = 0.5f * (b.hi[2] - b.lo[2]);
  const float reach = b.eps + m;
  const std::size_t n = g.n;
  for (std::size_t i = 0; i < n; i += SS_GEARS_LANES)
  {
    const VF x[3] = { Load(g.x0 + i), Load(g.x1 + i), Load(g.x2 + i) };
    const VF y[3] = { Load(g.y0 + i), Load(g.y1 + i), Load(g.y2 + i) };
    const VF z[3] = { Load(g.z0 + i), Load(g.z1 + i), Load(g.z2 + i) };
    // the group's list: GroupFilter's tests
    const VI valid = (lane + static_cast<int>(i)) < static_cast<int>(n);
    const VI k = GroupKeep(s.shaft, s.planes, s.np, x, y, z, valid, below);
    kept += static_cast<std::size_t>(__builtin_popcount(LaneMask(k)));
    // strictly between every start point and the light
    VI between = (b.lo[2] - z[0] > m) & (b.lo[2] - z[1] > m) & (b.lo[2] - z[2] > m);
    if (!b.dir)
    {
      between &= (b.cz + z[0] > m) & (b.cz + z[1] > m) & (b.cz + z[2] > m);
    }
    // every start point on one side of the plane
    const VF nx = Load(g.nx + i), ny = Load(g.ny + i), nz = Load(g.nz + i);
    const VF sigma = nx * cx + ny * cy + nz * cz - Load(g.nd + i);
    const VF ext = Abs(nx) * hx + Abs(ny) * hy + Abs(nz) * hz;
    const VF front = Load(g.front + i), back = Load(g.back + i);
    // the plane test for every start point: it hides nothing from the group
    const VI oneSide = ((sigma - ext > m) & (front > 0.5f)) | ((sigma + ext < -m) & (back > 0.5f));
    const VI inFront = sigma - ext > reach, behind = sigma + ext < -reach;
    VI nb[3];
    for (int e = 0; e < 3; ++e)
    {
      __builtin_memcpy(&nb[e], s.nbr[e] + i, sizeof(nb[e]));
    }
    // (a neighbour in the cell's list: one outside the group's adds a
    // contour edge that does not cancel, which is still exact)
    const VI linked = (nb[0] >= 0) | (nb[1] >= 0) | (nb[2] >= 0);
    const VI ok = k & between & linked & (front >= 0.0f) & ~oneSide;
    const VI st = ok ? (inFront ? VI{} + 1 : (behind ? VI{} + 2 : VI{})) : VI{};
    __builtin_memcpy(s.status + i, &st, sizeof(st));
    if (!LaneMask(k))
    {
      continue;
    }
    const VI member = st != 0;
    if (LaneMask(member))
    {
      for (int col = 0; col < 9; ++col)
      {
        Compact(Load(src[col] + i), member, s.member[col] + nm);
      }
      for (int e = 0; e < 3; ++e)
      {
        Compact(nb[e], member, s.memberNbr[e] + nm);
      }
      Compact(st, member, s.memberStatus + nm);
      VUI idx;
      __builtin_memcpy(&idx, ids + i, sizeof(idx));
      nm += static_cast<std::size_t>(Compact(idx, member, s.memberIds + nm));
    }
    // wholly beyond every start point, or behind the light
    VI useless = oneSide | ((z[0] - b.hi[2] > m) & (z[1] - b.hi[2] > m) & (z[2] - b.hi[2] > m));
    if (!b.dir)
    {
      useless |= (b.cz + z[0] < -m) & (b.cz + z[1] < -m) & (b.cz + z[2] < -m);
    }
    const VI other = k & (st == 0) & ~useless;
    if (LaneMask(other))
    {
      for (int col = 0; col < 15; ++col)
      {
        Compact(Load(src[col] + i), other, s.rest[col] + nr);
      }
      VUI idx;
      __builtin_memcpy(&idx, ids + i, sizeof(idx));
      nr += static_cast<std::size_t>(Compact(idx, other, s.restIds + nr));
    }
  }
  s.memberCount = nm;
  s.restCount = nr;
  s.kept = kept;
  s.below += static_cast<std::size_t>(below);
}

static inline std::size_t ContourEdges(const MemberSplit& s, ContourEdgeList& out)
{
  VI lane;
  for (int q = 0; q < SS_GEARS_LANES; ++q)
  {
    lane[q] = q;
  }
  std::size_t c = 0;
  const std::size_t n = s.memberCount;
  for (std::size_t i = 0; i < n; i += SS_GEARS_LANES)
  {
    VI st;
    __builtin_memcpy(&st, s.memberStatus + i, sizeof(st));
    const VI valid = lane + static_cast<int>(i) < VI{} + static_cast<int>(n);
    for (int m = 0; m < 3; ++m)
    {
      VI nb;
      __builtin_memcpy(&nb, s.memberNbr[m] + i, sizeof(nb));
      const VI has = valid & (nb >= 0);
      const VI sn = GatherI(s.status, nb & kNbrIndex, has);
      const VI same = (nb & kNbrSameDirection) != 0;
      // exact negations (ssGearsWinding.cxx): same side and opposite
      // traversal, or opposite sides and the same traversal
      const VI cancel = has & (sn != 0) & (same ? sn != st : sn == st);
      const VI keep = valid & ~cancel;
      if (!LaneMask(keep))
      {
        continue;
      }
      const int b = (m + 1) % 3;
      for (int a = 0; a < 3; ++a)
      {
        Compact(Load(s.member[3 * m + a] + i), keep, out.p[a] + c);
        Compact(Load(s.member[3 * b + a] + i), keep, out.p[3 + a] + c);
      }
      c += static_cast<std::size_t>(Compact((VUI)((lane + static_cast<int>(i)) | (m << 30)), keep, out.id + c));
    }
  }
  return c;
}

static inline std::size_t ContourPixel(const ContourEdgeList& e, const PixelParams& p, std::uint32_t* out)
{
  VI lane;
  for (int q = 0; q < SS_GEARS_LANES; ++q)
  {
    lane[q] = q;
  }
  const float m = p.m;
  const float gnum = p.dir ? 1.0f : p.Sz;
  const float Sxo = p.dir ? 0.0f : p.Sx, Syo = p.dir ? 0.0f : p.Sy;
  const float bx = Sxo * p.kx + p.off, by = Syo * p.ky + p.off;
  const float ax = std::abs(Sxo * p.kx), ay = std::abs(Syo * p.ky);
  const VF zero = VF{} + 0.0f, last = zero + p.last;
  const std::size_t n = e.n;
  std::size_t c = 0;
  for (std::size_t i = 0; i < n; i += SS_GEARS_LANES)
  {
    // every vertex lies between S and the light (members): d > 0
    const VF da = p.sz - Load(e.p[2] + i), db = p.sz - Load(e.p[5] + i);
    const VI inRange = lane + static_cast<int>(i) < VI{} + static_cast<int>(n);
    const VF qa = gnum / (inRange ? da : zero + 1.0f), qb = gnum / (inRange ? db : zero + 1.0f);
    const VF ua = (Load(e.p[0] + i) - p.sx) * qa * p.kx, ub = (Load(e.p[3] + i) - p.sx) * qb * p.kx;
    const VF va = (Load(e.p[1] + i) - p.sy) * qa * p.ky, vb = (Load(e.p[4] + i) - p.sy) * qb * p.ky;
    const VF qm = Max(qa, qb);
    const VF mu = 1e-4f * (Max(Abs(ua), Abs(ub)) + ax) + m * qm * p.kx + 1e-3f;
    const VF mv = 1e-4f * (Max(Abs(va), Abs(vb)) + ay) + m * qm * p.ky + 1e-3f;
    // [ylo, yhi] holds an integer of 0 .. k - 1, and not right of every sample
    const VF ylo = Min(va, vb) + by - mv, yhi = Max(va, vb) + by + mv;
    const VF lo = Max(ylo, zero - 1.0f), hi = Min(yhi, last + 1.0f);
    const VF fhi = __builtin_convertvector(__builtin_convertvector(hi + 2.0f, VI), VF) - 2.0f; // floor
    const VF flo = __builtin_convertvector(__builtin_convertvector(lo + 2.0f, VI), VF) - 2.0f;
    const VF clo = flo + (flo < lo ? VF{} + 1.0f : zero); // ceil
    const VI rows = (clo <= fhi) & (fhi >= zero) & (clo <= last);
    const VI right = Min(ua, ub) + bx - mu > last;
    const VI keep = inRange & rows & ~right;
    if (LaneMask(keep))
    {
      c += static_cast<std::size_t>(Compact((VUI)(lane + static_cast<int>(i)), keep, out + c));
    }
  }
  return c;
}

// ContourSteps: the exact steps of kept contour edges for one pixel, kRowLanes
// edges at a time, with the operations of WindingMask's scalar form (and of
// SetupTriangle, MakeAffine, RowBound): per edge the light-frame vertices from
// the solver's floats (ia, ib: float offsets of its two vertices), their
// projections (the rows the edge spans, half-open per vertex), its function
// sg (a x b) and per row its bound, +1 / -1 into delta (k rows of k + 1).
// Returns the number of edges that stepped a row, or -1 when the pixel is
// declined (a vertex within rounding of a row near the samples, an edge
// along the rows).
static inline int ContourSteps(const ExactSource& src, const std::int32_t* ia, const std::int32_t* ib,
  const double* sgs, std::size_t n, const ExactPixel& p, std::int16_t* delta)
{
  const int k = p.k;
  const double kx = double(k) / p.W, ky = double(k) / p.H, hk = 0.5 * k - 0.5;
  const double D0x = p.dir ? 0.0 : -p.Sx, D0y = p.dir ? 0.0 : -p.Sy, D0z = p.dir ? -1.0 : -p.Sz;
  const double h = 0.5 * p.invK - 0.5;
  const VD zero = VD{} + 0.0, one = VD{} + 1.0, kmax = VD{} + (k - 1.0);
  VD lane;
  for (int q = 0; q < kRowLanes; ++q)
  {
    lane[q] = double(q);
  }
  int stepped = 0;
  for (std::size_t e0 = 0; e0 < n; e0 += kRowLanes)
  {
    const int count = static_cast<int>(std::min<std::size_t>(kRowLanes, n - e0));
    const VL valid = lane < double(count);
    VD B[2][3];
    for (int v = 0; v < 2; ++v)
    {
      // (the arrays hold kRowLanes valid entries past n: the caller repeats one)
      const std::int32_t* idx = (v == 0 ? ia : ib) + e0;
      const VD X[3] = { GatherAt(src.V, idx), GatherAt(src.V + 1, idx), GatherAt(src.V + 2, idx) };
      const VD rx = X[0] - src.Lc[0], ry = X[1] - src.Lc[1], rz = X[2] - src.Lc[2];
      B[v][0] = (rx * src.u[0] + ry * src.u[1]) + rz * src.u[2];
      B[v][1] = (rx * src.v[0] + ry * src.v[1]) + rz * src.v[2];
      B[v][2] = (rx * src.n[0] + ry * src.n[1]) + rz * src.n[2];
    }
    // projections in sample units (WindingMask's Project)
    // (tx, ty: 1e-14 of the magnitudes the projection's sums cancel, in
    // sample units, about 9 times their rounding (some 10 roundings of
    // 2^-53 each). They matter only for a light tiny beside its distance:
    // below about 1e-7 of it the 1e-7 terms no longer cover the rounding.)
    VD px[2], py[2], tx[2], ty[2];
    for (int v = 0; v < 2; ++v)
    {
      const VD q = (p.dir ? VD{} + 1.0 : VD{} + p.Sz) / (p.Sz - B[v][2]);
      const double ox = p.dir ? 0.0 : p.Sx, oy = p.dir ? 0.0 : p.Sy;
      px[v] = (ox + (B[v][0] - p.Sx) * q) * kx + hk;
      py[v] = (oy + (B[v][1] - p.Sy) * q) * ky + hk;
      const VD aq = q < 0.0 ? -q : q;
      const VD bx = B[v][0] < 0.0 ? -B[v][0] : B[v][0], by = B[v][1] < 0.0 ? -B[v][1] : B[v][1];
      tx[v] = 1e-14 * ((std::abs(ox) + (bx + std::abs(p.Sx)) * aq) * kx);
      ty[v] = 1e-14 * ((std::abs(oy) + (by + std::abs(p.Sy)) * aq) * ky);
    }
    // a vertex within rounding of a row near the samples: declined
    for (int v = 0; v < 2; ++v)
    {
      const VD yr = __builtin_convertvector(__builtin_convertvector(py[v] + 0.5 + 4.0, VJ), VD) - 4.0; // round (y > -4.5)
      const VD ad = py[v] - yr;
      const VL near = (yr >= 0.0) & (yr <= k - 1.0) &
        ((ad < 0.0 ? -ad : ad) <= 1e-7 * (1.0 + (py[v] < 0.0 ? -py[v] : py[v])) + ty[v]) &
        (px[v] >= -1.0 - tx[v]) & (px[v] <= double(k) + tx[v]);
      if (RowMask(near & valid))
      {
        return -1;
      }
    }
    const VD y0 = py[0] < py[1] ? py[0] : py[1], y1 = py[0] < py[1] ? py[1] : py[0];
    const VD xmin = px[0] < px[1] ? px[0] : px[1];
    const VD ax0 = px[0] < 0.0 ? -px[0] : px[0], ax1 = px[1] < 0.0 ? -px[1] : px[1];
    // rows j0 .. j1 (clamped to the samples; y within [-2, k + 1] or out)
    const VD c0 = y0 < -2.0 ? zero - 2.0 : (y0 > k + 1.0 ? VD{} + (k + 1.0) : y0);
    const VD c1 = y1 < -2.0 ? zero - 2.0 : (y1 > k + 1.0 ? VD{} + (k + 1.0) : y1);
    const VD t0 = __builtin_convertvector(__builtin_convertvector(c0, VJ), VD);
    const VD t1 = __builtin_convertvector(__builtin_convertvector(c1, VJ), VD);
    const VD ceil0 = t0 + (t0 < c0 ? one : zero), ceil1 = t1 + (t1 < c1 ? one : zero);
    const VD j0 = ceil0 < 0.0 ? zero : ceil0;
    const VD j1 = (ceil1 - 1.0) > kmax ? kmax : ceil1 - 1.0;
    const VL live = valid & (j0 <= j1) & !(xmin > (k - 1.0) + 1e-7 * (1.0 + ax0 + ax1) + tx[0] + tx[1]);
    const unsigned liveBits = RowMask(live);
    if (!liveBits)
    {
      continue;
    }
    // the edge's function as SetupTriangle computes it: sg (a x b)
    VD sg;
    for (int q = 0; q < kRowLanes; ++q)
    {
      sg[q] = sgs[e0 + (q < count ? q : 0)];
    }
    const VD axv = B[0][0] - p.Sx, ayv = B[0][1] - p.Sy, azv = B[0][2] - p.Sz;
    const VD bxv = B[1][0] - p.Sx, byv = B[1][1] - p.Sy, bzv = B[1][2] - p.Sz;
    const VD ex = sg * (ayv * bzv - byv * azv), ey = sg * (azv * bxv - bzv * axv), ez = sg * (axv * byv - bxv * ayv);
    const VD du = (ex * p.W + ey * 0.0) + ez * 0.0, dv = (ex * 0.0 + ey * p.H) + ez * 0.0;
    const VD A = (0.0 + ((ex * D0x + ey * D0y) + ez * D0z)) + h * (du + dv);
    const VD Bc = du * p.invK, C = dv * p.invK;
    if (RowMask(live & !(Bc != 0.0)))
    {
      return -1;
    }
    const VD Bs = Bc != 0.0 ? Bc : one;
    const VD P = -A / Bs, Q = -C / Bs;
    const VL steep = !(((P < 0.0 ? -P : P) <= kSteepKernel) & ((Q < 0.0 ? -Q : Q) <= kSteepKernel));
    // (the division per row only where a live edge needs it: steep is rare)
    const bool anySteep = RowMask(live & steep) != 0;
    const VD span = live ? j1 - j0 : zero - 1.0;
    double most = -1.0;
    for (int q = 0; q < kRowLanes; ++q)
    {
      most = std::max(most, span[q]);
    }
    stepped += __builtin_popcount(liveBits);
    const int rows = static_cast<int>(most) + 1;
    std::int16_t step[kRowLanes];
    for (int q = 0; q < kRowLanes; ++q)
    {
      step[q] = Bc[q] > 0.0 ? 1 : -1;
    }
    for (int r = 0; r < rows; ++r)
    {
      const VD jv = j0 + double(r);
      const VL on = live & (jv <= j1);
      // RowBound, both signs of B at once
      const VD ej = A + C * jv;
      VD x = P + Q * jv;
      if (anySteep)
      {
        x = steep ? -ej / Bs : x;
      }
      x = x < -2.0 ? zero - 2.0 : (x > k + 1.0 ? VD{} + (k + 1.0) : x);
      const VD t = __builtin_convertvector(__builtin_convertvector(x, VJ), VD);
      const VD cu = t + (t < x ? one : zero), cd = t - (t > x ? one : zero); // ceil, floor
      const VD emL = ej + Bc * (cu - 1.0), e0L = ej + Bc * cu;
      const VD lo = emL >= 0.0 ? cu - 1.0 : (e0L >= 0.0 ? cu : cu + 1.0);
      const VD epU = ej + Bc * (cd + 1.0), e0U = ej + Bc * cd;
      const VD hi = epU >= 0.0 ? cd + 1.0 : (e0U >= 0.0 ? cd : cd - 1.0);
      const VD at = Bc > 0.0 ? lo : hi + 1.0;
      unsigned put = RowMask(on & (at <= k - 1.0));
      if (!put)
      {
        continue;
      }
      const VJ cell = __builtin_convertvector(jv, VJ) * (k + 1) + __builtin_convertvector(at < 0.0 ? zero : at, VJ);
      while (put)
      {
        const int q = __builtin_ctz(put);
        put &= put - 1;
        delta[cell[q]] += step[q];
      }
    }
  }
  return stepped;
}

// CountRows: the winding count's rows from its steps (delta: k rows of k + 1,
// at least 32 x 33 readable), a row at a time in 32 16-bit lanes: a log-step
// prefix sum, then the lanes with a positive count. Returns false when a
// count is negative (a contour that does not close).
typedef std::int16_t VS __attribute__((vector_size(64)));
static inline bool CountRows(const std::int16_t* delta, int k, std::uint32_t* rows)
{
  const VS z = VS{};
  const std::uint32_t use = k == 32 ? 0xFFFFFFFFu : ((1u << k) - 1u);
  std::uint32_t negative = 0;
  for (int j = 0; j < k; ++j)
  {
    VS v;
    __builtin_memcpy(&v, delta + j * (k + 1), sizeof(v));
    v += __builtin_shufflevector(v, z, 32, 0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15, 16, 17, 18, 19, 20, 21, 22, 23, 24, 25, 26, 27, 28, 29, 30);
    v += __builtin_shufflevector(v, z, 32, 33, 0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15, 16, 17, 18, 19, 20, 21, 22, 23, 24, 25, 26, 27, 28, 29);
    v += __builtin_shufflevector(v, z, 32, 33, 34, 35, 0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15, 16, 17, 18, 19, 20, 21, 22, 23, 24, 25, 26, 27);
    v += __builtin_shufflevector(v, z, 32, 33, 34, 35, 36, 37, 38, 39, 0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15, 16, 17, 18, 19, 20, 21, 22, 23);
    v += __builtin_shufflevector(v, z, 32, 33, 34, 35, 36, 37, 38, 39, 40, 41, 42, 43, 44, 45, 46, 47, 0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15);
    const VS pos = v > z, neg = v < z;
    std::uint32_t bits = 0, nb = 0;
#if SS_GEARS_LANES == 16
    bits = _mm512_movepi16_mask(reinterpret_cast<const __m512i&>(pos));
    nb = _mm512_movepi16_mask(reinterpret_cast<const __m512i&>(neg));
#else
    for (int q = 0; q < 32; ++q)
    {
      bits |= pos[q] ? 1u << q : 0u;
      nb |= neg[q] ? 1u << q : 0u;
    }
#endif
    rows[j] = bits & use;
    negative |= nb & use;
  }
  return negative == 0;
}

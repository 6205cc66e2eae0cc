// softshadows bench --gears --silhouette-probe STRIDE: whether the
// silhouette-edge winding raster (ssGearsSilhouette.h) would pay on a
// captured frame. For every STRIDE-th lit pixel and every closed piece: the
// silhouette mask with all of the piece's edges, the triangle raster of all
// of the piece's faces (both unculled: bit identity and the cost per item),
// how many silhouette edges cross the sample rows and how many cross the
// light's samples (what a per-cell edge list with a reference count, Laine
// et al. 2005, would have to hold), how many edges the per-cell candidate
// rule keeps for the box of the pixel's cell's start points, against the
// length of the pixel's GEARS
// list (its sample group's triangles after every culling rule), summed
// separately over the pixels the winding raster declined (per reason) and
// those it solved: the share of GEARS's per-pixel work it could take.
#include "ssBenchGearsFrame.h"

#include "ssGearsSilhouette.h"

#include <chrono>
#include <cmath>
#include <map>

namespace ssapp
{
namespace bench
{
nlohmann::json SilhouetteProbe(const GearsFrame& f, const ss::GearsSolver& gears, int k, int stride)
{
  using Clock = std::chrono::steady_clock;
  auto ms = [](Clock::time_point a) { return std::chrono::duration<double, std::milli>(Clock::now() - a).count(); };
  // the closed pieces, welded, with their edges
  const auto t0 = Clock::now();
  std::map<std::uint32_t, std::vector<glm::dvec3>> tris;
  for (std::size_t t = 0; t < f.tris.size() / 3; ++t)
  {
    const std::uint32_t p = f.pieces.piece[t];
    if (p < f.pieces.orientation.size() && f.pieces.orientation[p] != 0 && f.opacity[t] >= 1.0f)
    {
      tris[p].insert(tris[p].end(), { f.tris[3 * t], f.tris[3 * t + 1], f.tris[3 * t + 2] });
    }
  }
  std::vector<ss::GearsSilhouettePiece> pieces;
  std::vector<std::vector<glm::dvec3>> pieceTris;
  std::size_t notBuilt = 0;
  for (auto& pt : tris)
  {
    ss::GearsSilhouettePiece sp;
    if (sp.Build(pt.second))
    {
      pieces.push_back(std::move(sp));
      pieceTris.push_back(std::move(pt.second));
    }
    else
    {
      ++notBuilt;
    }
  }
  const double msBuild = ms(t0);
  // the pixels' GEARS lists (the assignment output lists every blocker)
  ss::GearsOptions go;
  go.k = k;
  ss::GearsAssignment as;
  const std::size_t n = f.pos.size() / 3;
  gears.Solve(f.light, f.origin, f.pos.data(), f.nrm.data(), n, go, nullptr, nullptr, &as);
  nlohmann::json out{ { "k", k }, { "stride", stride }, { "pieces", pieces.size() }, { "pieces_not_built", notBuilt },
    { "ms_build_edges", msBuild } };
  std::size_t probed = 0, solved = 0, identical = 0, edgesTotal = 0;
  double sil = 0, strip = 0, rect = 0, crossings = 0, listed = 0, msSil = 0, msTri = 0, faces = 0;
  std::map<std::string, std::size_t> declined;
  std::map<std::string, double> listedDeclined; // their pixels' GEARS list lengths, summed
  std::size_t lit = 0;
  // per (face, cell): the box of its pixels' start points (the per-cell
  // candidate rule's input)
  std::map<std::pair<std::int32_t, std::int32_t>, std::pair<glm::dvec3, glm::dvec3>> cellBox;
  for (std::size_t i = 0; i < n; ++i)
  {
    if (std::isnan(f.pos[3 * i]) || as.pixelFace[i] < 0)
    {
      continue;
    }
    const glm::dvec3 P = f.origin + glm::dvec3(f.pos[3 * i], f.pos[3 * i + 1], f.pos[3 * i + 2]);
    const glm::dvec3 S = gears.RayStart(f.light, P, glm::dvec3(f.nrm[3 * i], f.nrm[3 * i + 1], f.nrm[3 * i + 2]));
    auto it = cellBox.emplace(std::make_pair(as.pixelFace[i], as.pixelCell[i]), std::make_pair(S, S)).first;
    it->second.first = glm::min(it->second.first, S);
    it->second.second = glm::max(it->second.second, S);
  }
  double cellCandidates = 0;
  for (const auto& p : pieces)
  {
    edgesTotal += p.edges.size();
  }
  for (std::size_t i = 0; i < n; ++i)
  {
    if (std::isnan(f.pos[3 * i]) || as.pixelFace[i] < 0 || lit++ % static_cast<std::size_t>(stride) != 0)
    {
      continue;
    }
    const glm::dvec3 P = f.origin + glm::dvec3(f.pos[3 * i], f.pos[3 * i + 1], f.pos[3 * i + 2]);
    const glm::dvec3 N(f.nrm[3 * i], f.nrm[3 * i + 1], f.nrm[3 * i + 2]);
    const glm::dvec3 S = gears.RayStart(f.light, P, N);
    const double eps = glm::length(S - P) / std::max(glm::length(N), 1e-300);
    const auto& face = as.faces[as.pixelFace[i]];
    const std::int32_t g = as.pixelGroup[i];
    const double list = g >= 0 ? double(face.groupBegin[g + 1] - face.groupBegin[g]) : 0.0;
    ++probed;
    for (std::size_t q = 0; q < pieces.size(); ++q)
    {
      ss::GearsMask m{}, r{};
      ss::GearsSilhouetteStats st;
      auto t1 = Clock::now();
      const bool ok = ss::GearsSilhouetteMask(f.light, S, pieces[q], k, eps, m, &st);
      const double a = ms(t1);
      if (!ok)
      {
        ++declined[st.declined];
        listedDeclined[st.declined] += list;
        continue;
      }
      t1 = Clock::now();
      for (std::size_t t = 0; t < pieceTris[q].size() / 3; ++t)
      {
        ss::GearsRasterizeTriangle(f.light, S, { pieceTris[q][3 * t], pieceTris[q][3 * t + 1], pieceTris[q][3 * t + 2] }, k, r);
      }
      msTri += ms(t1);
      msSil += a;
      faces += double(pieces[q].faces.size());
      ++solved;
      identical += m == r;
      sil += double(st.silhouetteEdges);
      strip += double(st.stripEdges);
      rect += double(st.rectEdges);
      crossings += double(st.rowCrossings);
      listed += list;
      // the per-cell candidate rule over the pixel's cell's box of starts
      const auto& box = cellBox.at(std::make_pair(as.pixelFace[i], as.pixelCell[i]));
      for (std::size_t e = 0; e < pieces[q].edges.size(); ++e)
      {
        cellCandidates += ss::GearsEdgeMaySilhouette(pieces[q], e, box.first, box.second) ? 1.0 : 0.0;
      }
    }
  }
  auto per = [&](double x) { return solved ? x / double(solved) : 0.0; };
  out["pixels_probed"] = probed;
  out["piece_pixels_solved"] = solved;
  out["identical_to_triangle_raster"] = identical;
  out["declined"] = declined;
  out["gears_listed_declined_sum"] = listedDeclined;
  out["gears_listed_solved_sum"] = listed;
  out["edges_total"] = edgesTotal;
  out["faces_per_solve"] = per(faces);
  out["silhouette_edges_per_pixel"] = per(sil);
  out["strip_edges_per_pixel"] = per(strip);
  out["rect_edges_per_pixel"] = per(rect);
  out["row_crossings_per_pixel"] = per(crossings);
  out["gears_listed_per_pixel"] = per(listed);
  out["cell_candidate_edges_per_pixel"] = per(cellCandidates);
  out["ms_silhouette_all_edges_per_pixel"] = per(msSil);
  out["ms_triangle_raster_all_faces_per_pixel"] = per(msTri);
  return out;
}
}
}

// Checks what `softshadows render` wrote: the stats JSON contract of
// DESIGN.md and the visibility/positions buffers (same layout, NaN background,
// V in [0,1]), plus the shadow content expected of the scene.
//   ssCheckOutputs STATS VIS POS MODE     MODE: soft | lit | empty
#include "ssImageIO.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <fstream>
#include <iostream>

int main(int argc, char* argv[])
{
  if (argc != 5)
  {
    std::cerr << "usage: ssCheckOutputs STATS VIS POS soft|lit|empty\n";
    return 2;
  }
  const std::string mode = argv[4];
  int failures = 0;
  auto check = [&](bool ok, const std::string& what) {
    std::cout << (ok ? "ok:   " : "FAIL: ") << what << "\n";
    failures += ok ? 0 : 1;
  };
  nlohmann::json s;
  try
  {
    std::ifstream in(argv[1]);
    s = nlohmann::json::parse(in);
  }
  catch (const std::exception& e)
  {
    std::cerr << "FAIL: stats is not JSON: " << e.what() << "\n";
    return 1;
  }
  for (const char* k : { "method", "width", "height", "triangles", "positions_origin", "plan",
         "timings_ms", "memory_bytes" })
  {
    check(s.contains(k), std::string("stats has ") + k);
  }
  if (failures)
  {
    return 1;
  }
  check(s["positions_origin"].is_array() && s["positions_origin"].size() == 3, "positions_origin is [x,y,z]");
  check(s["timings_ms"].contains("total") && s["timings_ms"]["total"].get<double>() > 0.0, "timings_ms.total > 0");
  check(s["plan"].contains("lights") && s["plan"].contains("reason"), "plan has lights and reason");

  std::vector<float> V, P;
  int w, h, c, w2, h2, c2;
  std::string msg;
  if (!ssapp::ReadFloatImage(argv[2], V, w, h, c, msg) || !ssapp::ReadFloatImage(argv[3], P, w2, h2, c2, msg))
  {
    std::cerr << "FAIL: " << msg << "\n";
    return 1;
  }
  check(c == 1 && c2 == 3, "visibility has 1 channel, positions 3");
  check(w == w2 && h == h2 && w == s["width"].get<int>() && h == s["height"].get<int>(), "same size as stats");
  long mismatch = 0, outOfRange = 0, lit = 0, umbra = 0, penumbra = 0, fg = 0;
  for (std::size_t i = 0; i < V.size(); ++i)
  {
    const bool vb = std::isnan(V[i]), pb = std::isnan(P[3 * i]);
    mismatch += (vb != pb) ? 1 : 0;
    if (vb)
    {
      continue;
    }
    ++fg;
    if (!std::isfinite(V[i]) || V[i] < 0.0f || V[i] > 1.0f)
    {
      ++outOfRange;
    }
    else if (V[i] > 0.99f)
    {
      ++lit;
    }
    else if (V[i] < 0.02f)
    {
      ++umbra;
    }
    else
    {
      ++penumbra;
    }
  }
  std::cout << "foreground " << fg << ", lit " << lit << ", umbra " << umbra << ", penumbra " << penumbra << "\n";
  check(mismatch == 0, "visibility is NaN exactly where positions are NaN");
  check(outOfRange == 0, "finite visibility in [0,1]");
  if (mode == "soft")
  {
    check(lit > fg / 10, "lit pixels");
    check(umbra > 200, "umbra pixels");
    check(penumbra > 2000, "penumbra pixels (soft shadows, not hard)");
  }
  else if (mode == "lit")
  {
    check(fg > 0 && lit + penumbra == fg && umbra == 0, "no umbra");
  }
  else if (mode == "empty")
  {
    check(fg == 0, "empty scene: every pixel is background");
  }
  return failures ? 1 : 0;
}

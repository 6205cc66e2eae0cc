// Random GEARS test scenes shared by the CPU solver's tests (TestSSGEARS) and
// the GL compute backend's (TestGearsGL): triangles in a slab over a
// receiver, pixel samples on the receiver and on tilted patches, and five
// lights covering every light type and every cube face of a point light.
#ifndef ssGearsTestScenes_h
#define ssGearsTestScenes_h

#include "ssLightFrame.h"

#include <random>
#include <vector>

namespace sstest
{
struct Scene
{
  std::vector<glm::dvec3> tris;
  std::vector<float> pos, nrm;
};

// Random small triangles in a slab between a receiver plane z = 0 (with
// bumps: random normals) and the light, plus receivers as pixel samples.
inline Scene RandomScene(std::mt19937& rng, int ntri, int npix, const glm::dvec3& offset)
{
  std::uniform_real_distribution<double> U(-1.0, 1.0), Z(0.05, 1.5), S(0.02, 0.4);
  Scene s;
  for (int t = 0; t < ntri; ++t)
  {
    const glm::dvec3 c(U(rng), U(rng), Z(rng));
    const double r = S(rng);
    for (int j = 0; j < 3; ++j)
    {
      s.tris.push_back(offset + c + r * glm::dvec3(U(rng), U(rng), 0.5 * U(rng)));
    }
  }
  for (int i = 0; i < npix; ++i)
  {
    // receivers on the floor and on random triangles' planes nearby
    const glm::dvec3 p(1.5 * U(rng), 1.5 * U(rng), (i % 4 == 0) ? Z(rng) : 0.0);
    glm::dvec3 n = (i % 4 == 0) ? glm::normalize(glm::dvec3(U(rng), U(rng), 1.2 + U(rng))) : glm::dvec3(0, 0, 1);
    s.pos.insert(s.pos.end(), { float(p.x), float(p.y), float(p.z) });
    s.nrm.insert(s.nrm.end(), { float(n.x), float(n.y), float(n.z) });
  }
  return s;
}

inline std::vector<ss::LightFrame> Lights(const glm::dvec3& offset)
{
  using namespace ss;
  return { MakeRectLightFrame(offset + glm::dvec3(0.3, -0.2, 3.0), { -0.1, 0.05, -1 }, { 0, 1, 0 }, { 1.2, 0.7 }),
    MakeRectLightFrame(offset + glm::dvec3(-2.0, 0.5, 2.0), { 0.7, -0.2, -0.6 }, { 0, 0, 1 }, { 0.5, 0.5 }),
    MakeDirectionalLightFrame({ 0.2, 0.1, -1 }, 0.1), MakePointLightFrame(offset + glm::dvec3(0.2, 0.1, 2.5)),
    // a point light among the casters: every cube face of the grid is used
    MakePointLightFrame(offset + glm::dvec3(0.0, 0.0, 0.8)) };
}
}

#endif

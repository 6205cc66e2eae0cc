// `softshadows bake`, `softshadows prepare` and `softshadows bench --filters`:
// the Filters module (SoftShadows::Filters) from the command line, no GPU.
#ifndef ssBake_h
#define ssBake_h

#include <string>
#include <vector>

namespace ssapp
{
/// softshadows bake SCENE.json --object I --output baked.vtp [--samples K]
///   [--method gears|reference]: object I's surface in world coordinates with
///   LightVisibility_<light> point arrays (vtkLightVisibilityFilter).
int Bake(const std::vector<std::string>& args);
/// softshadows prepare MESH --output prepared.vtp [--tolerance F]
///   [--cluster-size N] [--boxes plane|optimal|aligned] [--no-snap]
///   [--no-self-intersections] [--report report.json]: vtkShadowCasterPreparation
///   alone; prints its report.
int Prepare(const std::vector<std::string>& args);
/// softshadows bench --filters [--smoke] [--mesh M] [--points N] [--runs R] [--out DIR]:
///   preparation time per million triangles and baking time for an N-point surface.
int BenchFilters(const std::vector<std::string>& args);
/// softshadows bench --culling --mesh M [--frames N] [--out DIR] | --smoke:
/// PVSM and GEARS with and without the prepared caster set's culling
/// (ssBenchCulling.cxx).
int BenchCulling(const std::vector<std::string>& args);
}

#endif

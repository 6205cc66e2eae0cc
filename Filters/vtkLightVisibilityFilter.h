/**
 * @class   vtkLightVisibilityFilter
 * @brief   Bakes the visible fraction of each light at every point of a surface, on the CPU.
 *
 * For each point of the input surface and each light, the fraction of the
 * light's area (k x k regular samples) that the point sees past the casters,
 * as point-data arrays `LightVisibility_<i>` (float, 0..1). Runs on all cores
 * (TBB) and needs no render window, GPU or display: it works in pvbatch on a
 * cluster node.
 *
 * The numbers are those of the renderer's CPU solvers at the same samples:
 * Method GEARS (default) is ss::GearsSolver, the exact k x k visibility of
 * GEARS; Method REFERENCE is ss::ReferenceSolver, Embree ray casting with the
 * same regular samples. Both start a point's rays off the surface along its
 * normal by the renderer's scene-scaled offset, treat rect lights as
 * one-sided, and count light samples below the point's tangent plane as not
 * visible. Translucent casters (OpacityArrayName) let a transmittance through.
 *
 * Normals: the input's point normals when it has them (their direction says
 * which side of the surface is baked), else vtkPolyDataNormals' (consistent,
 * not split; not added to the output).
 *
 * Casters: the triangles of the optional second input (SetCasterConnection),
 * plus the input surface itself when InputCastsShadows is on (default).
 *
 * Lights: the lights given with AddLight/SetLights, in order: array i belongs
 * to the i-th light of the collection. A positional light with an area size
 * (vtkSoftShadowLight::SetAreaSize) is a one-sided rect light facing its focal
 * point; without one it is a point light (visibility 0 or 1); a directional
 * light uses its angular diameter (vtkSoftShadowLight::SetAngularDiameter).
 * Lights that are switched off, headlights (no camera here) and lights with
 * vtkSoftShadowLight::SetCastsShadows(false) get no array (their index is
 * skipped). With no lights given, the one rect light of LightCenter,
 * LightNormal (the direction it faces), LightUp and LightSize is baked as
 * `LightVisibility_0` (the ParaView properties).
 */
#ifndef vtkLightVisibilityFilter_h
#define vtkLightVisibilityFilter_h

#include "SoftShadowsFiltersModule.h"
#include "vtkPolyDataAlgorithm.h"

class vtkLight;
class vtkLightCollection;

class SOFTSHADOWSFILTERS_EXPORT vtkLightVisibilityFilter : public vtkPolyDataAlgorithm
{
public:
  static vtkLightVisibilityFilter* New();
  vtkTypeMacro(vtkLightVisibilityFilter, vtkPolyDataAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  enum
  {
    METHOD_GEARS = 0,
    METHOD_REFERENCE = 1
  };

  ///@{
  /**
   * The solver: GEARS (default) or the ray-traced reference.
   */
  vtkSetClampMacro(Method, int, METHOD_GEARS, METHOD_REFERENCE);
  vtkGetMacro(Method, int);
  void SetMethodToGears() { this->SetMethod(METHOD_GEARS); }
  void SetMethodToReference() { this->SetMethod(METHOD_REFERENCE); }
  ///@}

  ///@{
  /**
   * k: k x k regular light samples, 1..32 (default 16).
   */
  vtkSetClampMacro(Samples, int, 1, 32);
  vtkGetMacro(Samples, int);
  ///@}

  ///@{
  /**
   * Whether the input surface casts shadows too (on itself and the rest).
   * Default on.
   */
  vtkSetMacro(InputCastsShadows, bool);
  vtkGetMacro(InputCastsShadows, bool);
  vtkBooleanMacro(InputCastsShadows, bool);
  ///@}

  /**
   * The casters: a vtkPolyData whose polygons and strips cast shadows.
   */
  void SetCasterConnection(vtkAlgorithmOutput* output) { this->SetInputConnection(1, output); }
  void SetCasterData(vtkDataObject* data) { this->SetInputData(1, data); }

  ///@{
  /**
   * A cell array of the casters with each cell's opacity in [0, 1] (1 opaque,
   * 0 casts nothing), read from the casters and from the input surface when
   * it casts; a surface without it is opaque, and none having it is an
   * error (a misspelt name). Unset or empty (default): every caster is opaque.
   */
  vtkSetStringMacro(OpacityArrayName);
  vtkGetStringMacro(OpacityArrayName);
  ///@}

  ///@{
  /**
   * The lights to bake (see the class description). SetLights replaces them.
   */
  void AddLight(vtkLight* light);
  void RemoveAllLights();
  void SetLights(vtkLightCollection* lights);
  vtkLightCollection* GetLights() { return this->Lights; }
  ///@}

  ///@{
  /**
   * The rect light baked when no lights were given: centre, the direction it
   * faces, its height edge direction and its width and height (world units).
   * A zero size is a point light.
   */
  vtkSetVector3Macro(LightCenter, double);
  vtkGetVector3Macro(LightCenter, double);
  vtkSetVector3Macro(LightNormal, double);
  vtkGetVector3Macro(LightNormal, double);
  vtkSetVector3Macro(LightUp, double);
  vtkGetVector3Macro(LightUp, double);
  vtkSetVector2Macro(LightSize, double);
  vtkGetVector2Macro(LightSize, double);
  ///@}

  vtkMTimeType GetMTime() override;

protected:
  vtkLightVisibilityFilter();
  ~vtkLightVisibilityFilter() override;

  int FillInputPortInformation(int port, vtkInformation* info) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  int Method = METHOD_GEARS;
  int Samples = 16;
  bool InputCastsShadows = true;
  char* OpacityArrayName = nullptr;
  vtkLightCollection* Lights;
  double LightCenter[3] = { 0.0, 0.0, 5.0 };
  double LightNormal[3] = { 0.0, 0.0, -1.0 };
  double LightUp[3] = { 0.0, 1.0, 0.0 };
  double LightSize[2] = { 1.0, 1.0 };

private:
  vtkLightVisibilityFilter(const vtkLightVisibilityFilter&) = delete;
  void operator=(const vtkLightVisibilityFilter&) = delete;
};

#endif

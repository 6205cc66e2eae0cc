#include "ssGBuffer.h"

#include "ssFrameState.h"
#include "ssTextureArray.h"

#include "vtkCamera.h"
#include "vtkMatrix4x4.h"
#include "vtkNew.h"
#include "vtkOpenGLFramebufferObject.h"
#include "vtkOpenGLRenderWindow.h"
#include "vtkOpenGLState.h"
#include "vtkRenderer.h"
#include "vtkShaderProgram.h"
#include "vtkTextureObject.h"
#include "vtk_glew.h"

#include <glm/glm.hpp>

#include <limits>

namespace ss
{
void GBuffer::Begin(vtkRenderer* ren, vtkOpenGLRenderWindow* win, vtkOpenGLFramebufferObject* fbo, const FrameState& frame)
{
  vtkOpenGLState* ostate = win->GetState();
  const int w = frame.Width, h = frame.Height;
  this->HaveCPUCopy = false;

  EnsureTexture2D(win, this->Position, w, h, 4);
  EnsureTexture2D(win, this->Normal, w, h, 4);
  EnsureTexture2D(win, this->GeometricNormal, w, h, 4);
  if (!this->Depth)
  {
    this->Depth = vtkSmartPointer<vtkTextureObject>::New();
    this->Depth->SetContext(win);
    this->Depth->AllocateDepth(w, h, vtkTextureObject::Float32);
  }
  else if (static_cast<int>(this->Depth->GetWidth()) != w || static_cast<int>(this->Depth->GetHeight()) != h)
  {
    this->Depth->Resize(w, h);
  }

  // Camera matrices in double: VC -> world relative to the frame origin.
  vtkCamera* cam = ren->GetActiveCamera();
  vtkMatrix4x4* view = cam->GetModelViewTransformMatrix(); // WC -> VC, row-major
  glm::dmat3 R;
  glm::dvec3 t;
  for (int r = 0; r < 3; ++r)
  {
    for (int c = 0; c < 3; ++c)
    {
      R[c][r] = view->GetElement(r, c); // glm is column-major: R[col][row]
    }
    t[r] = view->GetElement(r, 3);
  }
  const glm::dmat3 Rt = glm::transpose(R);
  const glm::dvec3 off = -(Rt * t) - frame.Origin;
  for (int c = 0; c < 3; ++c)
  {
    for (int r = 0; r < 3; ++r)
    {
      this->VCToWC[c * 3 + r] = static_cast<float>(Rt[c][r]);
    }
    this->VCToRelOffset[c] = static_cast<float>(off[c]);
  }
  vtkNew<vtkMatrix4x4> proj;
  proj->DeepCopy(cam->GetProjectionTransformMatrix(ren->GetTiledAspectRatio(), -1, 1));
  proj->Invert();
  for (int c = 0; c < 4; ++c)
  {
    for (int r = 0; r < 4; ++r)
    {
      this->DCToVC[c * 4 + r] = static_cast<float>(proj->GetElement(r, c));
    }
  }

  ostate->PushFramebufferBindings();
  fbo->Bind();
  fbo->AddColorAttachment(0, this->Position);
  fbo->AddColorAttachment(1, this->Normal);
  fbo->AddColorAttachment(2, this->GeometricNormal);
  fbo->AddDepthAttachment(this->Depth);
  fbo->ActivateDrawBuffers(NumberOfTargets);
  ostate->vtkglViewport(0, 0, w, h);
  ostate->vtkglScissor(0, 0, w, h);
  ostate->vtkglDisable(GL_BLEND);
  ostate->vtkglEnable(GL_DEPTH_TEST);
  ostate->vtkglDepthMask(GL_TRUE);
  ostate->vtkglClearColor(0.0, 0.0, 0.0, 0.0);
  ostate->vtkglClearDepth(1.0);
  ostate->vtkglClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
}

void GBuffer::End(vtkOpenGLRenderWindow* win, vtkOpenGLFramebufferObject* fbo)
{
  fbo->RemoveColorAttachments(NumberOfTargets);
  fbo->RemoveDepthAttachment();
  win->GetState()->PopFramebufferBindings();
}

void GBuffer::InjectOutputs(std::string& fragmentShader, std::size_t mainPos, std::size_t endPos)
{
  const bool haveVC = fragmentShader.find("vec4 vertexVC") != std::string::npos;
  const bool haveN = fragmentShader.find("normalVCVSOutput") != std::string::npos;
  std::string impl = "  {\n";
  if (haveVC)
  {
    impl += "    vec3 ssVC = vertexVC.xyz;\n";
  }
  else
  {
    impl += "    vec4 ssNDC = vec4(2.0 * (gl_FragCoord.xy / ssViewportSize) - 1.0,"
            " 2.0 * gl_FragCoord.z - 1.0, 1.0);\n"
            "    vec4 ssVC4 = ssDCToVC * ssNDC;\n"
            "    vec3 ssVC = ssVC4.xyz / ssVC4.w;\n";
  }
  impl += "    gl_FragData[0] = vec4(ssVCToWC * ssVC + ssVCToRelOffset, ssPropId);\n";
  // The geometric normal: the plane of the triangle being drawn, from the
  // screen derivatives of its view-space position (the 2x2 quad's helper
  // invocations extrapolate the same triangle, so this is the facet's plane
  // up to float rounding). It is oriented to the side of the shading normal
  // (to the camera when there is none). The shadow-map solvers take the
  // receiver's plane from it: a faceted surface with interpolated normals is
  // the facet, not the smooth normal's tangent plane (issue 17).
  // Each derivative is scaled by its largest component first: in a scene of
  // 1e12 units a pixel spans 5e9, the cross product's squared length passes
  // the float range, and the normal came out 0 with w = 1 (ASM then read
  // every receiver as facing away: a black picture; stop 45's Python sweep).
  impl += "    vec3 ssDX = dFdx(ssVC), ssDY = dFdy(ssVC);\n"
          "    float ssMX = max(max(abs(ssDX.x), abs(ssDX.y)), abs(ssDX.z));\n"
          "    float ssMY = max(max(abs(ssDY.x), abs(ssDY.y)), abs(ssDY.z));\n"
          "    vec3 ssGN = (ssMX > 0.0 && ssMY > 0.0) ? cross(ssDX / ssMX, ssDY / ssMY) : vec3(0.0);\n"
          "    float ssGL = length(ssGN);\n"
          "    ssGN = (ssGL > 0.0) ? ssGN / ssGL : vec3(0.0);\n";
  impl += haveN ? "    vec3 ssSN = normalize(normalVCVSOutput);\n"
                  "    ssGN = (dot(ssGN, ssSN) < 0.0) ? -ssGN : ssGN;\n"
                  "    gl_FragData[1] = vec4(ssVCToWC * ssSN, 1.0);\n"
                : "    ssGN = (dot(ssGN, ssVC) > 0.0) ? -ssGN : ssGN;\n"
                  "    gl_FragData[1] = vec4(0.0);\n";
  impl += "    gl_FragData[2] = vec4(ssVCToWC * ssGN, ssGL > 0.0 ? 1.0 : 0.0);\n";
  impl += "  }\n";
  fragmentShader.insert(endPos, impl);
  fragmentShader.insert(mainPos,
    "uniform mat3 ssVCToWC;\n"
    "uniform vec3 ssVCToRelOffset;\n"
    "uniform mat4 ssDCToVC;\n"
    "uniform vec2 ssViewportSize;\n"
    "uniform float ssPropId;\n");
}

void GBuffer::SetCameraUniforms(vtkShaderProgram* program) const
{
  program->SetUniformMatrix3x3("ssVCToWC", const_cast<float*>(this->VCToWC));
  program->SetUniform3f("ssVCToRelOffset", this->VCToRelOffset);
}

void GBuffer::SetShaderParameters(vtkShaderProgram* program, vtkProp* prop, int width, int height)
{
  auto it = this->PropIds.find(prop);
  if (it == this->PropIds.end())
  {
    it = this->PropIds.emplace(prop, static_cast<int>(this->PropIds.size()) + 1).first;
  }
  this->SetCameraUniforms(program);
  program->SetUniformMatrix4x4("ssDCToVC", this->DCToVC);
  const float vs[2] = { static_cast<float>(width), static_cast<float>(height) };
  program->SetUniform2f("ssViewportSize", vs);
  program->SetUniformf("ssPropId", static_cast<float>(it->second));
}

int GBuffer::FindPropId(vtkProp* prop) const
{
  const auto it = this->PropIds.find(prop);
  return it == this->PropIds.end() ? 0 : it->second;
}

bool GBuffer::Read(vtkOpenGLRenderWindow* win, vtkOpenGLFramebufferObject* fbo, int which, int w, int h,
  std::vector<float>& rgba) const
{
  vtkTextureObject* t =
    which == 0 ? this->Position.Get() : (which == 1 ? this->Normal.Get() : this->GeometricNormal.Get());
  return t && fbo && ReadTexture(win, fbo, t, 0, w, h, 4, rgba);
}

bool GBuffer::ReadForCPU(vtkOpenGLRenderWindow* win, vtkOpenGLFramebufferObject* fbo, int w, int h,
  const std::vector<float>*& positions, const std::vector<float>*& normals)
{
  if (!this->HaveCPUCopy)
  {
    std::vector<float> pos4, nrm4;
    this->Read(win, fbo, 0, w, h, pos4);
    this->Read(win, fbo, 1, w, h, nrm4);
    const std::size_t n = static_cast<std::size_t>(w) * h;
    this->CPUPositions.assign(3 * n, 0.0f);
    this->CPUNormals.assign(3 * n, 0.0f);
    const float nan = std::numeric_limits<float>::quiet_NaN();
    for (std::size_t i = 0; i < n && 4 * i + 3 < pos4.size() && 4 * i + 3 < nrm4.size(); ++i)
    {
      const bool fg = pos4[4 * i + 3] > 0.0f;
      for (int c = 0; c < 3; ++c)
      {
        this->CPUPositions[3 * i + c] = fg ? pos4[4 * i + c] : nan;
        this->CPUNormals[3 * i + c] = nrm4[4 * i + c];
      }
    }
    this->HaveCPUCopy = true;
  }
  positions = &this->CPUPositions;
  normals = &this->CPUNormals;
  return true;
}

long long GBuffer::Bytes() const
{
  return TextureBytes(this->Position, 16) + TextureBytes(this->Normal, 16) + TextureBytes(this->GeometricNormal, 16) +
    TextureBytes(this->Depth, 4);
}

int GBuffer::CountGraphicsResources() const
{
  int n = 0;
  for (vtkTextureObject* t :
    { this->Position.Get(), this->Normal.Get(), this->GeometricNormal.Get(), this->Depth.Get() })
  {
    n += (t && t->GetHandle() != 0) ? 1 : 0;
  }
  return n;
}

void GBuffer::ReleaseGraphicsResources(vtkWindow* w)
{
  for (auto* t : { this->Position.Get(), this->Normal.Get(), this->GeometricNormal.Get(), this->Depth.Get() })
  {
    if (t)
    {
      t->ReleaseGraphicsResources(w);
    }
  }
  this->Position = nullptr;
  this->Normal = nullptr;
  this->GeometricNormal = nullptr;
  this->Depth = nullptr;
  this->HaveCPUCopy = false;
  this->CPUPositions.clear();
  this->CPUNormals.clear();
}
}

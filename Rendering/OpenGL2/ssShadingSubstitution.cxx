#include "ssShadingSubstitution.h"

#include "ssFrameState.h"
#include "ssReceiverCapture.h"
#include "ssTranslucentReceivers.h"

#include "vtkShaderProgram.h"

#include <cctype>
#include <utility>

namespace ss
{
int InjectVisibility(std::string& fragmentShader, int translucentLookups, bool capture, FragmentCode code)
{
  int lightsInShader = 0;
  while (fragmentShader.find("lightColor" + std::to_string(lightsInShader)) != std::string::npos)
  {
    ++lightsInShader;
  }
  const bool headlightOnly =
    fragmentShader.find("vec3 diffuse = df * diffuseColor * lightColor0;") != std::string::npos;
  // VTK declares the light uniforms for a Points or Wireframe representation
  // without normals too, and then writes ambient + diffuse colour only: no
  // light term uses them (a ParaView Wavelet shown as Points logged an error
  // per frame here)
  bool used = false;
  for (int i = 0; i < lightsInShader && !used; ++i)
  {
    const std::string name = "lightColor" + std::to_string(i);
    int uses = 0;
    for (std::size_t at = fragmentShader.find(name); at != std::string::npos; at = fragmentShader.find(name, at + 1))
    {
      const std::size_t end = at + name.size();
      const bool whole = end >= fragmentShader.size() || !std::isdigit(static_cast<unsigned char>(fragmentShader[end]));
      const bool declaration = at >= 5 && fragmentShader.compare(at - 5, 5, "vec3 ") == 0;
      uses += (whole && !declaration) ? 1 : 0;
    }
    used = uses > 0;
  }
  if (lightsInShader == 0 || headlightOnly || !used)
  {
    return 0; // unlit, or a headlight (which never casts shadows)
  }
  int hits = 0;
  std::string perLight;
  for (int i = 0; i < lightsInShader; ++i)
  {
    const std::string n = std::to_string(i);
    const std::string vis = "ssVisibility(ssLightLayer" + n + ", ssLightColorLayer" + n + ")";
    const std::string diffuse = "diffuse += (df * lightColor" + n + ");";
    const std::string specular = "specular += (sf * lightColor" + n + ");";
    const std::size_t d = fragmentShader.find(diffuse), sp = fragmentShader.find(specular);
    // The specular term takes the V the diffuse term computed just before
    // (in VTK's Phong code both are in one block, diffuse first): a
    // translucent receiver's V is its fragment's whole filter, which
    // llvmpipe would otherwise run twice per light.
    const bool reuse = d != std::string::npos && sp != std::string::npos && d < sp;
    perLight += "vec3 ssVis" + n + " = vec3(1.0);\n";
    const std::pair<std::string, std::string> subs[] = {
      { diffuse, "{ ssVis" + n + " = " + vis + "; diffuse += (df * lightColor" + n + " * ssVis" + n + "); }" },
      { specular, "specular += (sf * lightColor" + n + " * " + (reuse ? "ssVis" + n : vis) + ");" },
      { "radiance = lightColor" + n + ";", "radiance = lightColor" + n + " * " + vis + ";" },
      { "radiance = lightColor" + n + " * attenuation;",
        "radiance = lightColor" + n + " * attenuation * " + vis + ";" },
    };
    for (const auto& sub : subs)
    {
      hits += vtkShaderProgram::Substitute(fragmentShader, sub.first, sub.second, false) ? 1 : 0;
    }
  }
  if (hits < lightsInShader)
  {
    return lightsInShader - hits;
  }
  std::string decl = "uniform sampler2D ssGPosition;\n"
                     "uniform sampler2DArray ssVisTex;\n"
                     "uniform sampler2DArray ssVisColorTex;\n"
                     "uniform vec2 ssViewportOrigin;\n"
                     "uniform float ssPropId;\n"
                     "uniform int ssUseVis;\n";
  for (int i = 0; i < lightsInShader; ++i)
  {
    decl += "uniform int ssLightLayer" + std::to_string(i) + ";\n";
    decl += "uniform int ssLightColorLayer" + std::to_string(i) + ";\n";
  }
  // props that are not in the G-buffer (translucent ones) get the
  // visibility of their own fragments from the solvers that can give it
  decl += TranslucentReceiverCode(fragmentShader, capture, translucentLookups, code);
  decl += "vec3 ssVisibility(int layer, int colorLayer)\n"
          "{\n"
          "  if (ssUseVis == 0 || layer < 0) { return vec3(1.0); }\n"
          "  if (ssPropId < 0.5) { return ssFragmentVisibility(layer); }\n"
          "  ivec2 pix = ivec2(gl_FragCoord.xy - ssViewportOrigin);\n"
          "  vec4 g = texelFetch(ssGPosition, pix, 0);\n"
          "  // only the surface that is in the G-buffer\n"
          "  if (abs(g.w - ssPropId) > 0.5) { return vec3(1.0); }\n"
          "  if (colorLayer >= 0) { return clamp(texelFetch(ssVisColorTex, ivec3(pix, colorLayer), 0).rgb, 0.0, 1.0); }\n"
          "  return vec3(clamp(texelFetch(ssVisTex, ivec3(pix, layer), 0).r, 0.0, 1.0));\n"
          "}\n";
  decl += perLight;
  fragmentShader.insert(fragmentShader.find("void main"), decl);
  const bool listed = translucentLookups != 0 && code == FragmentCode::Listed;
  const bool captured = translucentLookups != 0 && capture;
  RequireExtensions(fragmentShader, listed, captured);
  return 0;
}

void RequireExtensions(std::string& fs, bool storage, bool images)
{
  // VTK puts its #version line (150) where //VTK::System::Dec is; an
  // #extension must follow it before any declaration
  const std::string marker = "//VTK::System::Dec";
  const std::size_t at = fs.find(marker);
  if (at == std::string::npos || (!storage && !images))
  {
    return;
  }
  std::string lines = "\n";
  if (storage)
  {
    lines += "#extension GL_ARB_shader_storage_buffer_object : require\n"
             "#extension GL_ARB_shading_language_420pack : require\n"
             "#extension GL_ARB_shader_bit_encoding : require\n";
  }
  if (images)
  {
    lines += "#extension GL_ARB_shader_image_load_store : require\n";
  }
  fs.insert(at + marker.size(), lines);
}

void InjectRecord(std::string& fs, std::size_t mainPos, std::size_t endPos, int lookups)
{
  fs.insert(endPos, "  ssRecordThisFragment();\n");
  fs.insert(mainPos, TranslucentReceiverCode(fs, false, lookups, FragmentCode::Record));
  // early tests need image load/store's layout
  const bool early = fs.find("gl_FragDepth") == std::string::npos;
  if (early)
  {
    fs.insert(fs.find("void main"), "layout(early_fragment_tests) in;\n");
  }
  RequireExtensions(fs, true, early);
}

void SetVisibilityUniforms(vtkShaderProgram* program, const ShadingUniforms& u, const std::vector<ShadowLight>& lights)
{
  program->SetUniformi("ssUseVis", u.Use ? 1 : 0);
  // Samplers always point at the bound textures: two sampler types left on
  // unit 0 make every draw of that shader fail (GL_INVALID_OPERATION).
  program->SetUniformi("ssGPosition", u.PositionUnit);
  program->SetUniformi("ssVisTex", u.VisibilityUnit);
  if (program->IsUniformUsed("ssVisColorTex"))
  {
    program->SetUniformi("ssVisColorTex", u.ColorUnit >= 0 ? u.ColorUnit : u.VisibilityUnit);
  }
  if (u.Use)
  {
    const float vo[2] = { static_cast<float>(u.ViewportOrigin[0]), static_cast<float>(u.ViewportOrigin[1]) };
    program->SetUniform2f("ssViewportOrigin", vo);
    program->SetUniformf("ssPropId", static_cast<float>(u.PropId));
  }
  for (const auto& l : lights)
  {
    const std::string name = "ssLightLayer" + std::to_string(l.ShaderIndex);
    if (program->IsUniformUsed(name.c_str()))
    {
      program->SetUniformi(name.c_str(), u.Use ? l.Layer : -1);
    }
    const std::string color = "ssLightColorLayer" + std::to_string(l.ShaderIndex);
    if (program->IsUniformUsed(color.c_str()))
    {
      program->SetUniformi(color.c_str(), u.Use ? l.ColorLayer : -1);
    }
  }
}
}

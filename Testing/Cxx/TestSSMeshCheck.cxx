// IO/Core: the format guards on byte buffers (no VTK). Each refusal is one
// line that says what is wrong; each good file is accepted with its counts.
#include "ssImageCheck.h"
#include "ssMeshCheck.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>

using namespace ss::io;

namespace
{
MeshCheck Check(MeshFormat f, const std::string& s, const MeshLimits& l = {})
{
  return CheckMesh(f, s.data(), s.size(), l);
}

void ExpectRefused(const MeshCheck& r, const std::string& fragment)
{
  EXPECT_FALSE(r.Ok);
  EXPECT_NE(r.Error.find(fragment), std::string::npos) << "message: " << r.Error;
  EXPECT_EQ(r.Error.find('\n'), std::string::npos) << "not one line: " << r.Error;
}

std::string Bytes(const void* p, std::size_t n)
{
  return std::string(static_cast<const char*>(p), n);
}

std::string BinarySTL(std::uint32_t declared, int held, float x0 = 0.0f)
{
  std::string s(80, ' ');
  s += Bytes(&declared, 4);
  for (int t = 0; t < held; ++t)
  {
    const float v[12] = { 0, 0, 1, x0, 0, 0, 1, 0, 0, 0, 1, 0 };
    s += Bytes(v, 48);
    s += std::string(2, '\0');
  }
  s[0] = '\x01'; // header bytes count towards binary detection
  for (int i = 1; i < 20; ++i)
    s[i] = '\x02';
  return s;
}

const char* kPlyHeader = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                         "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n";
}

TEST(MeshCheck, FormatFromPath)
{
  EXPECT_EQ(FormatFromPath("a/b.OFF"), MeshFormat::OFF);
  EXPECT_EQ(FormatFromPath("x.Stl"), MeshFormat::STL);
  EXPECT_EQ(FormatFromPath("x.vtp"), MeshFormat::VTP);
  EXPECT_EQ(FormatFromPath("dir.ply/x"), MeshFormat::Unknown);
  EXPECT_EQ(FormatFromPath("x.gltf"), MeshFormat::Unknown);
}

TEST(MeshCheck, SizeLimitSaysWhatItWas)
{
  MeshLimits l;
  l.MaximumFileBytes = 10;
  ExpectRefused(Check(MeshFormat::OFF, "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n", l), "above the limit of 10 bytes");
  ExpectRefused(Check(MeshFormat::OFF, ""), "empty file");
}

TEST(MeshCheck, OFF)
{
  const std::string good = "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
  const MeshCheck r = Check(MeshFormat::OFF, good);
  ASSERT_TRUE(r.Ok) << r.Error;
  EXPECT_EQ(r.Vertices, 3u);
  EXPECT_EQ(r.Faces, 1u);
  ExpectRefused(Check(MeshFormat::OFF, "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n"), "vertex index '7' out of range [0, 2]");
  ExpectRefused(Check(MeshFormat::OFF, "OFF\n3 2 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n3 0 1 2\n3 0 1 2\n"),
    "data after the last of the 2 faces");
  ExpectRefused(Check(MeshFormat::OFF, "OFF\n3 3 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n3 0 1 2\n" + std::string(20, '\n')),
    "the file ends after 2 of the 3 faces");
  ExpectRefused(Check(MeshFormat::OFF, "OFF\n2000000000 1 0\n0 0 0\n"), "declares 2000000000 vertices");
  ExpectRefused(Check(MeshFormat::OFF, "OFF\n-5 1 0\n"), "vertex count '-5'");
  ExpectRefused(Check(MeshFormat::OFF, "OFF 3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"), "counts go on the next line");
  ExpectRefused(Check(MeshFormat::OFF, "COFF\n3 1 0\n"), "variant 'COFF' is not supported");
  ExpectRefused(Check(MeshFormat::OFF, "OFF\n# c\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"), "comment lines");
  ExpectRefused(Check(MeshFormat::OFF, "OFF\n3 1 0\n0 0 1e39\n1 0 0\n0 1 0\n3 0 1 2\n"), "not a finite number");
  ExpectRefused(Check(MeshFormat::OFF, "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2 255 0 0\n"), "face colours");
  // a face that repeats a vertex is counted (OpenMesh drops it; the reader warns)
  const MeshCheck d = Check(MeshFormat::OFF, "OFF\n3 2 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n3 0 0 1\n");
  ASSERT_TRUE(d.Ok) << d.Error;
  EXPECT_EQ(d.DegenerateFaces, 1u);
}

TEST(MeshCheck, STLBinary)
{
  const MeshCheck r = Check(MeshFormat::STL, BinarySTL(2, 2));
  ASSERT_TRUE(r.Ok) << r.Error;
  EXPECT_TRUE(r.Binary);
  EXPECT_EQ(r.Faces, 2u);
  EXPECT_EQ(r.NonFiniteVertices, 0u);
  ExpectRefused(Check(MeshFormat::STL, BinarySTL(1000000, 10)), "declares 1000000 triangles");
  ExpectRefused(Check(MeshFormat::STL, BinarySTL(1, 3)), "declares 1 triangles");
  ExpectRefused(Check(MeshFormat::STL, BinarySTL(0, 0)), "declares 0 triangles");
  const MeshCheck n = Check(MeshFormat::STL, BinarySTL(1, 1, std::nanf("")));
  ASSERT_TRUE(n.Ok);
  EXPECT_EQ(n.NonFiniteVertices, 1u); // the reader then turns point merging off
}

TEST(MeshCheck, STLAscii)
{
  const std::string facet = "facet normal 0 0 1\n outer loop\n  vertex 0 0 0\n  vertex 1 0 0\n  vertex 0 1 0\n endloop\nendfacet\n";
  const MeshCheck r = Check(MeshFormat::STL, "solid s\n" + facet + facet + "endsolid s\n");
  ASSERT_TRUE(r.Ok) << r.Error;
  EXPECT_FALSE(r.Binary);
  EXPECT_EQ(r.Faces, 2u);
  ExpectRefused(Check(MeshFormat::STL, "solid s\n" + facet.substr(0, facet.find("  vertex 0 1 0"))), "cut short");
  ExpectRefused(Check(MeshFormat::STL, "solid s\n" + facet), "before 'endsolid'");
  ExpectRefused(Check(MeshFormat::STL, "solid s\nfacet normal 0 0 1\n outer loop\n  vertex 0 0\n"), "three numbers");
  ExpectRefused(Check(MeshFormat::STL, "solid s\n" + std::string(300, 'x') + "\n"), "longer than 253");
}

TEST(MeshCheck, PLY)
{
  const MeshCheck r = Check(MeshFormat::PLY, std::string(kPlyHeader) + "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
  ASSERT_TRUE(r.Ok) << r.Error;
  EXPECT_EQ(r.Vertices, 3u);
  ExpectRefused(Check(MeshFormat::PLY, std::string(kPlyHeader) + "0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n"), "vertex index 7 out of range [0, 2]");
  ExpectRefused(Check(MeshFormat::PLY, std::string(kPlyHeader)), "but only 0 bytes follow");
  ExpectRefused(Check(MeshFormat::PLY, std::string(kPlyHeader) + "0.0 0.0 0.0\n1 0 0\n0 1 0\n3 0 1 2"), "no newline");
  ExpectRefused(Check(MeshFormat::PLY, std::string(kPlyHeader) + "0.0 0.0 0.0\n1 0\n0 1 0\n3 0 1 2\n"), "too few values");
  ExpectRefused(Check(MeshFormat::PLY, std::string(kPlyHeader) + "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n9 9 9\n"), "data after the last element");
  // face before vertex, an element VTK cannot skip, the vertex_index rewrite
  ExpectRefused(Check(MeshFormat::PLY, "ply\nformat ascii 1.0\nelement face 1\nproperty list uchar int vertex_indices\n"
                                       "element vertex 3\nproperty float x\nproperty float y\nproperty float z\nend_header\n"),
    "expected the elements 'vertex' and then 'face'");
  ExpectRefused(Check(MeshFormat::PLY, "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                                       "property float z\nelement material 1\nproperty float a\nelement face 1\n"
                                       "property list uchar int vertex_indices\nend_header\n"),
    "element 'material' before 'face'");
  // a second 'face' (or 'vertex') element: VTK reads it too, with indices
  // nobody checked (a fuzzed binary file crashed the reader)
  ExpectRefused(Check(MeshFormat::PLY, "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                                       "property float z\nelement face 1\nproperty list uchar int vertex_indices\n"
                                       "element face 1\nproperty list uchar int vertex_indices\nend_header\n"
                                       "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n3 0 1 99\n"),
    "a second element 'face'");
  ExpectRefused(Check(MeshFormat::PLY, "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                                       "property float z\nelement face 1\nproperty list uchar int vertex_indices\n"
                                       "element vertex 1\nproperty float x\nend_header\n"
                                       "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n5\n"),
    "a second element 'vertex'");
  std::string renamed = kPlyHeader;
  renamed.replace(renamed.find("vertex_indices"), 14, "vertex_index");
  EXPECT_TRUE(Check(MeshFormat::PLY, renamed + "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n").Ok);
  renamed = kPlyHeader;
  renamed.replace(renamed.find("vertex_indices"), 14, "vertex_indicevertex_indexs");
  ExpectRefused(Check(MeshFormat::PLY, renamed + "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"), "must be a scalar");
  // binary big endian, and a cut one
  std::string be = "ply\nformat binary_big_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                   "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n";
  const unsigned char one[4] = { 0x3f, 0x80, 0, 0 }; // 1.0f big-endian
  std::string verts(36, '\0');
  std::memcpy(&verts[12], one, 4);
  std::memcpy(&verts[28], one, 4);
  const unsigned char face[13] = { 3, 0, 0, 0, 0, 0, 0, 0, 1, 0, 0, 0, 2 };
  EXPECT_TRUE(Check(MeshFormat::PLY, be + verts + Bytes(face, 13)).Ok);
  const unsigned char bad[13] = { 3, 0, 0, 0, 0, 0, 0, 0, 1, 0, 0, 0, 3 };
  ExpectRefused(Check(MeshFormat::PLY, be + verts + Bytes(bad, 13)), "vertex index 3 out of range");
  ExpectRefused(Check(MeshFormat::PLY, be + verts + Bytes(face, 12)), "but only 48 bytes follow");
  const unsigned char big[13] = { 255, 0, 0, 0, 0, 0, 0, 0, 1, 0, 0, 0, 2 };
  ExpectRefused(Check(MeshFormat::PLY, be + verts + Bytes(big, 13)), "the file ends inside it");
}

TEST(MeshCheck, OBJ)
{
  const std::string v = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
  const MeshCheck r = Check(MeshFormat::OBJ, v + "vn 0 0 1\nvt 0 0\nf 1/1/1 2/1/1 3/1/1\nf -3//1 -2//1 -1//1\n");
  ASSERT_TRUE(r.Ok) << r.Error;
  EXPECT_EQ(r.Faces, 2u);
  ExpectRefused(Check(MeshFormat::OBJ, v + "f 0 1 2\n"), "vertex index 0 (OBJ indices start at 1)");
  ExpectRefused(Check(MeshFormat::OBJ, v + "f 1 2 99\n"), "vertex index 99 out of range");
  ExpectRefused(Check(MeshFormat::OBJ, v + "f 1 2 -99\n"), "vertex index -99 out of range");
  ExpectRefused(Check(MeshFormat::OBJ, "f 1 2 3\n" + v), "none defined yet");
  ExpectRefused(Check(MeshFormat::OBJ, v + "f 1/1 2/1 3/1\n"), "texture coordinate index 1 out of range");
  ExpectRefused(Check(MeshFormat::OBJ, v + "vt 0 0\nf 1/1 2 3\n"), "mix the forms");
  ExpectRefused(Check(MeshFormat::OBJ, v + "usemtl " + std::string(120, 'm') + "\nf 1 2 3\n"), "1 to 99 characters");
  ExpectRefused(Check(MeshFormat::OBJ, "v 0 0\n"), "needs 3 numbers");
  ExpectRefused(Check(MeshFormat::OBJ, "v 0 0 1e39\n"), "as a float");
  ExpectRefused(Check(MeshFormat::OBJ, v), "no faces");
}

TEST(MeshCheck, LegacyAndXML)
{
  EXPECT_TRUE(Check(MeshFormat::LegacyVTK, "# vtk DataFile Version 3.0\nt\nASCII\nDATASET POLYDATA\nPOINTS 3 float\n"
                                           "0 0 0 1 0 0 0 1 0\nPOLYGONS 1 4\n3 0 1 2\n").Ok);
  ExpectRefused(Check(MeshFormat::LegacyVTK, "# vtk DataFile Version 3.0\nt\nASCII\nDATASET POLYDATA\nPOINTS 2000000000 float\n0 0 0\n"),
    "'POINTS' declares data of at least");
  ExpectRefused(Check(MeshFormat::LegacyVTK, "# vtk DataFile Version 3.0\nt\nBINARY\nDATASET POLYDATA\nPOINTS 1000 float\n"),
    "'POINTS' declares data");
  ExpectRefused(Check(MeshFormat::LegacyVTK, "# vtk DataFile Version 3.0\nt\nASCII\nDATASET STRUCTURED_POINTS\nDIMENSIONS 100000 100000 100000\n"),
    "above the limit of 2^27 points");
  ExpectRefused(Check(MeshFormat::LegacyVTK, "hello"), "not a legacy VTK file");
  ExpectRefused(Check(MeshFormat::VTP, "binary\x01"), "not an XML file");
  ExpectRefused(Check(MeshFormat::VTP, "<VTKFile><Piece NumberOfPoints=\"999999999\">"), "more than a file of");
}

TEST(ImageCheck, PFM)
{
  const float px[2] = { 0.25f, 0.5f };
  const std::string good = "Pf\n2 1\n-1.0\n" + Bytes(px, 8);
  const ImageCheck r = CheckPFM(good.data(), good.size());
  ASSERT_TRUE(r.Ok) << r.Error;
  EXPECT_EQ(r.Width, 2);
  EXPECT_EQ(r.Channels, 1);
  const std::string zero = "Pf\n2 1\n0\n" + Bytes(px, 8);
  EXPECT_NE(CheckPFM(zero.data(), zero.size()).Error.find("scale '0'"), std::string::npos);
  const std::string huge = "Pf\n2000000000 2000000000\n-1.0\n" + Bytes(px, 8);
  EXPECT_NE(CheckPFM(huge.data(), huge.size()).Error.find("not two integers in [1, 65536]"), std::string::npos);
  const std::string cut = "PF\n2 1\n-1.0\n" + Bytes(px, 8);
  EXPECT_NE(CheckPFM(cut.data(), cut.size()).Error.find("2 x 1 x 3 floats"), std::string::npos);
  const std::string notpfm = "P6\n1 1\n255\nabc";
  EXPECT_FALSE(CheckPFM(notpfm.data(), notpfm.size()).Ok);
}

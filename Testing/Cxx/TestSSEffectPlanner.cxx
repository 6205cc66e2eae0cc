// Effect planner v1 (DESIGN.md "effect plan"): one test per rule, the
// catalogue of methods it plans with, and the JSON/text the stats and
// PrintSelf show.
#include "ssEffectPlanner.h"

#include <gtest/gtest.h>

using namespace ss;

namespace
{
bool Contains(const std::string& s, const std::string& part)
{
  return s.find(part) != std::string::npos;
}

PlannerLight Area()
{
  PlannerLight l;
  l.frame = MakeRectLightFrame({ 0, 0, 5 }, { 0, 0, -1 }, { 0, 1, 0 }, { 1, 1 });
  return l;
}

PlannerLight Point()
{
  PlannerLight l;
  l.frame = MakePointLightFrame({ 0, 0, 5 });
  return l;
}

// The methods as the solver registry (Rendering/OpenGL2/ssSolverRegistry.cxx)
// lists them; TestSoftShadowPass checks that the registry gives the planner
// this catalogue.
std::vector<MethodInfo> Catalogue()
{
  return { { Method::Auto, "auto", PlannerRule::OnRequest, false },
    { Method::None, "none", PlannerRule::OnRequest, false },
    { Method::Hard, "hard", PlannerRule::HardLights, false }, { Method::PCF, "pcf", PlannerRule::OnRequest, false },
    { Method::PCSS, "pcss", PlannerRule::SoftLights, false },
    { Method::PVSM, "pvsm", PlannerRule::OnRequest, false },
    { Method::HardAverage, "hardavg", PlannerRule::OnRequest, false },
    { Method::Reference, "reference", PlannerRule::OnRequest, true },
    { Method::GEARS, "gears", PlannerRule::OnRequest, true },
    { Method::VPCSS, "vpcss", PlannerRule::TranslucentCasters, true, true },
    { Method::AVSM, "avsm", PlannerRule::OnRequest, true, true } };
}

PlannerInput Scene(std::vector<PlannerLight> lights)
{
  PlannerInput in;
  in.methods = Catalogue();
  in.casterTriangles = 100;
  in.receiverProps = 2;
  in.lights = std::move(lights);
  return in;
}
}

TEST(EffectPlanner, NamesAndRulesComeFromTheCatalogue)
{
  // the plan names each light's method as the catalogue does
  PlannerInput in = Scene({ Area(), Point() });
  EffectPlan p = MakeEffectPlan(in);
  EXPECT_EQ(p.lights[0].name, "pcss");
  EXPECT_EQ(p.lights[1].name, "hard");
  in.requested = Method::Reference;
  p = MakeEffectPlan(in);
  EXPECT_EQ(p.lights[0].method, Method::Reference);
  EXPECT_EQ(p.lights[0].name, "reference");
  // auto uses whichever method is registered for the rule
  for (auto& m : in.methods)
  {
    m.rule = m.method == Method::PVSM ? PlannerRule::SoftLights
                                      : (m.method == Method::PCSS ? PlannerRule::OnRequest : m.rule);
  }
  in.requested = Method::Auto;
  p = MakeEffectPlan(in);
  EXPECT_EQ(p.lights[0].method, Method::PVSM);
  EXPECT_TRUE(Contains(p.lights[0].reason, "area light: soft shadows (PVSM)")) << p.lights[0].reason;
  EXPECT_EQ(p.lights[1].method, Method::Hard);
  // a rule nobody serves, and a request for a method that is not registered,
  // plan no shadows and say why
  PlannerInput bare = Scene({ Area(), Point() });
  bare.methods = { { Method::None, "none", PlannerRule::OnRequest, false },
    { Method::Hard, "hard", PlannerRule::HardLights, false } };
  p = MakeEffectPlan(bare);
  EXPECT_EQ(p.lights[0].method, Method::None);
  EXPECT_EQ(p.lights[0].name, "none");
  EXPECT_TRUE(Contains(p.lights[0].reason, "no method is registered")) << p.lights[0].reason;
  EXPECT_EQ(p.lights[1].method, Method::Hard);
  bare.requested = Method::GEARS;
  p = MakeEffectPlan(bare);
  EXPECT_EQ(p.lights[0].method, Method::None);
  EXPECT_TRUE(Contains(p.lights[0].reason, "method 6 is not a registered method")) << p.lights[0].reason;
  EXPECT_FALSE(p.shadowWork);
  // FindMethod
  ASSERT_NE(FindMethod(in.methods, Method::GEARS), nullptr);
  EXPECT_EQ(FindMethod(in.methods, Method::GEARS)->name, "gears");
  EXPECT_EQ(FindMethod(bare.methods, Method::GEARS), nullptr);
}

TEST(EffectPlanner, NothingToShadow)
{
  struct Case
  {
    PlannerInput in;
    const char* reason;
  };
  PlannerInput noLights = Scene({});
  PlannerInput noCasters = Scene({ Area(), Point() });
  noCasters.casterTriangles = 0;
  PlannerInput noReceivers = Scene({ Area(), Point() });
  noReceivers.receiverProps = 0;
  for (const Case& c : { Case{ noLights, "no lights" }, Case{ noCasters, "no shadow casters" },
         Case{ noReceivers, "no shadow receivers" } })
  {
    for (bool unchanged : { false, true })
    {
      PlannerInput in = c.in;
      in.unchangedSinceLastFrame = unchanged;
      const EffectPlan p = MakeEffectPlan(in);
      EXPECT_FALSE(p.shadowWork) << c.reason;
      EXPECT_FALSE(p.reuse) << c.reason; // nothing to reuse without shadow work
      EXPECT_TRUE(Contains(p.reason, c.reason)) << p.reason;
      ASSERT_EQ(p.lights.size(), in.lights.size());
      for (const LightPlan& l : p.lights)
      {
        EXPECT_EQ(l.method, Method::None);
        EXPECT_TRUE(Contains(l.reason, c.reason)) << l.reason;
      }
    }
  }
  // requesting "none" switches the whole frame off
  PlannerInput off = Scene({ Area() });
  off.requested = Method::None;
  const EffectPlan p = MakeEffectPlan(off);
  EXPECT_FALSE(p.shadowWork);
  EXPECT_EQ(p.lights[0].method, Method::None);
}

TEST(EffectPlanner, LightsThatCastNoShadows)
{
  PlannerLight head = Area();
  head.headlight = true;
  PlannerLight off = Area();
  off.castsShadows = false;
  PlannerLight bad = Area();
  bad.valid = false;
  bad.invalidReason = "zero normal";
  for (Method requested : { Method::Auto, Method::Hard, Method::PCF, Method::PCSS })
  {
    PlannerInput in = Scene({ head, off, bad });
    in.requested = requested;
    const EffectPlan p = MakeEffectPlan(in);
    ASSERT_EQ(p.lights.size(), 3u);
    EXPECT_EQ(p.lights[0].method, Method::None);
    EXPECT_TRUE(Contains(p.lights[0].reason, "headlight")) << p.lights[0].reason;
    EXPECT_EQ(p.lights[1].method, Method::None);
    EXPECT_TRUE(Contains(p.lights[1].reason, "light does not cast shadows")) << p.lights[1].reason;
    EXPECT_EQ(p.lights[2].method, Method::None);
    EXPECT_TRUE(Contains(p.lights[2].reason, "zero normal")) << p.lights[2].reason;
    EXPECT_FALSE(p.shadowWork); // none of them needs a visibility solve
  }
}

TEST(EffectPlanner, AutoPicksBySoftness)
{
  PlannerLight thin = Area();
  thin.frame = MakeRectLightFrame({ 0, 0, 5 }, { 0, 0, -1 }, { 0, 1, 0 }, { 1, 0 });
  PlannerLight sun;
  sun.frame = MakeDirectionalLightFrame({ 0, 0, -1 }, 0.0093);
  PlannerLight hardSun;
  hardSun.frame = MakeDirectionalLightFrame({ 0, 0, -1 }, 0.0);
  const EffectPlan p = MakeEffectPlan(Scene({ Area(), Point(), thin, sun, hardSun }));
  ASSERT_EQ(p.lights.size(), 5u);
  EXPECT_TRUE(p.shadowWork);
  EXPECT_FALSE(p.reuse);
  EXPECT_EQ(p.lights[0].method, Method::PCSS);
  EXPECT_TRUE(Contains(p.lights[0].reason, "area light: soft shadows (PCSS)")) << p.lights[0].reason;
  EXPECT_EQ(p.lights[1].method, Method::Hard);
  EXPECT_TRUE(Contains(p.lights[1].reason, "point/zero-size light: hard shadows")) << p.lights[1].reason;
  EXPECT_EQ(p.lights[2].method, Method::Hard); // one zero side: not soft
  EXPECT_EQ(p.lights[3].method, Method::PCSS); // the sun has an angular size
  EXPECT_EQ(p.lights[4].method, Method::Hard);
}

TEST(EffectPlanner, RequestedMethodForEveryShadowCastingLight)
{
  PlannerLight head = Point();
  head.headlight = true;
  for (Method requested : { Method::Hard, Method::PCF, Method::PCSS })
  {
    PlannerInput in = Scene({ Area(), Point(), head });
    in.requested = requested;
    const EffectPlan p = MakeEffectPlan(in);
    EXPECT_TRUE(p.shadowWork);
    EXPECT_EQ(p.lights[0].method, requested);
    EXPECT_EQ(p.lights[1].method, requested); // even a point light gets what was asked for
    EXPECT_EQ(p.lights[2].method, Method::None);
    EXPECT_TRUE(Contains(p.lights[0].reason, FindMethod(in.methods, requested)->name)) << p.lights[0].reason;
  }
  // PCSS on a point light degenerates to a hard shadow, and the reason says so
  PlannerInput in = Scene({ Area(), Point() });
  in.requested = Method::PCSS;
  const EffectPlan p = MakeEffectPlan(in);
  EXPECT_TRUE(Contains(p.lights[1].reason, "degenerates")) << p.lights[1].reason;
  EXPECT_FALSE(Contains(p.lights[0].reason, "degenerates")) << p.lights[0].reason;
}

TEST(EffectPlanner, TranslucentCastersAndReuse)
{
  PlannerInput in = Scene({ Area() });
  in.translucentCasters = true;
  EffectPlan p = MakeEffectPlan(in);
  EXPECT_TRUE(Contains(p.reason, "translucent casters are treated as opaque by pcss")) << p.reason;
  EXPECT_FALSE(p.reuse);
  // solvers that weigh casters by opacity need no such note
  in.requested = Method::Reference;
  EXPECT_FALSE(Contains(MakeEffectPlan(in).reason, "translucent")) << MakeEffectPlan(in).reason;
  in.requested = Method::Auto;
  in.translucentCasters = false;
  EXPECT_FALSE(Contains(MakeEffectPlan(in).reason, "translucent"));

  in.unchangedSinceLastFrame = true;
  in.lastMethods = { Method::PCSS };
  p = MakeEffectPlan(in);
  EXPECT_TRUE(p.shadowWork);
  EXPECT_TRUE(p.reuse);
  EXPECT_EQ(p.Summary(), "pcss (reused)");
  EXPECT_EQ(p.lights[0].method, Method::PCSS); // the plan itself still says what V holds
  // V computed with another method is not reused (an interactive frame's
  // stand-in must not become the still frame's picture)
  in.lastMethods = { Method::Hard };
  EXPECT_FALSE(MakeEffectPlan(in).reuse);
  in.lastMethods = {};
  EXPECT_FALSE(MakeEffectPlan(in).reuse);
  // reuse needs shadow work: a headlight-only scene has nothing to reuse
  PlannerLight head = Area();
  head.headlight = true;
  PlannerInput h = Scene({ head });
  h.unchangedSinceLastFrame = true;
  p = MakeEffectPlan(h);
  EXPECT_FALSE(p.shadowWork);
  EXPECT_FALSE(p.reuse);
  EXPECT_EQ(p.Summary(), "none: no light casts shadows");
}

TEST(EffectPlanner, JSONAndText)
{
  PlannerLight bad = Area();
  bad.valid = false;
  bad.invalidReason = "size \"-1\" is negative\\\nsecond line";
  const EffectPlan p = MakeEffectPlan(Scene({ Area(), bad }));
  const std::string j = p.ToJSON();
  EXPECT_EQ(j.front(), '{');
  EXPECT_EQ(j.back(), '}');
  EXPECT_TRUE(Contains(j, "\"shadow_work\": true")) << j;
  EXPECT_TRUE(Contains(j, "\"reuse\": false")) << j;
  EXPECT_TRUE(Contains(j, "\"reason\": \"")) << j;
  EXPECT_TRUE(Contains(j, "{\"method\": \"pcss\", \"reason\": \"")) << j;
  EXPECT_TRUE(Contains(j, "{\"method\": \"none\"")) << j;
  // quotes, backslashes and newlines are escaped; no raw control characters
  EXPECT_TRUE(Contains(j, "size \\\"-1\\\" is negative\\\\\\nsecond line")) << j;
  for (char c : j)
  {
    EXPECT_GE(static_cast<unsigned char>(c), 0x20);
  }
  // a small scanner: strings close, escapes are valid, brackets balance outside strings
  bool inString = false;
  int depth = 0;
  for (std::size_t i = 0; i < j.size(); ++i)
  {
    const char c = j[i];
    if (inString)
    {
      if (c == '\\')
      {
        ASSERT_LT(i + 1, j.size());
        EXPECT_NE(std::string("\"\\/bfnrtu").find(j[i + 1]), std::string::npos) << j;
        ++i;
      }
      else if (c == '"')
      {
        inString = false;
      }
    }
    else if (c == '"')
    {
      inString = true;
    }
    else if (c == '{' || c == '[')
    {
      ++depth;
    }
    else if (c == '}' || c == ']')
    {
      --depth;
      ASSERT_GE(depth, 0) << j;
    }
  }
  EXPECT_FALSE(inString) << j;
  EXPECT_EQ(depth, 0) << j;
  const std::string t = p.ToText();
  EXPECT_TRUE(Contains(t, "light 0: pcss")) << t;
  EXPECT_TRUE(Contains(t, "light 1: none")) << t;
  EXPECT_TRUE(Contains(t, p.reason)) << t;
  EXPECT_EQ(MakeEffectPlan(Scene({})).ToJSON().find("\"lights\": []") != std::string::npos, true);
}

// Lights 0 (an area light) and 1 (a point light) planned VPCSS, soft and
// hard, each reason naming why (`why0`, `why1`).
void ExpectVPCSSSoftAndHard(const EffectPlan& p, const std::string& why0, const std::string& why1)
{
  ASSERT_GE(p.lights.size(), 2u);
  EXPECT_EQ(p.lights[0].method, Method::VPCSS);
  EXPECT_TRUE(Contains(p.lights[0].reason, why0)) << p.lights[0].reason;
  EXPECT_TRUE(Contains(p.lights[0].reason, "soft shadows (VPCSS)")) << p.lights[0].reason;
  EXPECT_EQ(p.lights[1].method, Method::VPCSS);
  EXPECT_TRUE(Contains(p.lights[1].reason, why1)) << p.lights[1].reason;
  EXPECT_TRUE(Contains(p.lights[1].reason, "hard shadows")) << p.lights[1].reason;
}

// The translucent rule (VPCSS): a light with a translucent caster in its
// view (opacity < 1, an RGBA texture or a volume, as the pass finds it) gets
// the method registered for TranslucentCasters, soft or not, and the reason
// names what is translucent; other lights keep their rules. Volumes alone
// are casters.
TEST(EffectPlanner, TranslucentCastersInViewGetVPCSS)
{
  PlannerLight glass = Area();
  glass.translucentInView = "opacity < 1";
  PlannerLight smoke = Point();
  smoke.translucentInView = "a volume";
  PlannerInput in = Scene({ glass, smoke, Area(), Point() });
  in.translucentCasters = true;
  in.casterVolumes = 1;
  EffectPlan p = MakeEffectPlan(in);
  ExpectVPCSSSoftAndHard(p, "translucent casters in its view (opacity < 1)", "(a volume)");
  EXPECT_EQ(p.lights[2].method, Method::PCSS); // nothing translucent can shadow its receivers
  EXPECT_EQ(p.lights[3].method, Method::Hard);
  EXPECT_TRUE(Contains(p.reason, "1 caster volume(s)")) << p.reason;
  // the lights on opaque-only methods are named in the frame's note
  EXPECT_TRUE(Contains(p.reason, "treated as opaque and volumes cast no shadows by pcss, hard")) << p.reason;
  // an explicit request wins over the rule
  in.requested = Method::PCSS;
  EXPECT_EQ(MakeEffectPlan(in).lights[0].method, Method::PCSS);
  // vpcss requested: lights with a translucent caster in view get it; a light
  // whose casters are all opaque gets PCSS (VPCSS is PCSS there), and says why
  in.requested = Method::VPCSS;
  p = MakeEffectPlan(in);
  EXPECT_EQ(p.lights[0].method, Method::VPCSS);
  EXPECT_EQ(p.lights[1].method, Method::VPCSS);
  EXPECT_EQ(p.lights[2].method, Method::PCSS);
  EXPECT_TRUE(Contains(p.lights[2].reason, "no translucent caster in this light's view")) << p.lights[2].reason;
  EXPECT_EQ(p.lights[2].name, "pcss");
  // keepRequested: that light gets vpcss as asked
  in.keepRequested = true;
  p = MakeEffectPlan(in);
  EXPECT_EQ(p.lights[2].method, Method::VPCSS);
  EXPECT_EQ(p.lights[2].reason, "requested vpcss");
  in.keepRequested = false;
  // without a method for the rule, the soft and hard rules apply
  in.requested = Method::Auto;
  for (auto& m : in.methods)
  {
    m.rule = m.method == Method::VPCSS ? PlannerRule::OnRequest : m.rule;
  }
  EXPECT_EQ(MakeEffectPlan(in).lights[0].method, Method::PCSS);
  // a volume is a caster: no triangles, still shadow work
  PlannerInput v = Scene({ smoke });
  v.casterTriangles = 0;
  v.casterVolumes = 1;
  p = MakeEffectPlan(v);
  EXPECT_TRUE(p.shadowWork);
  EXPECT_EQ(p.lights[0].method, Method::VPCSS);
  v.casterVolumes = 0;
  EXPECT_FALSE(MakeEffectPlan(v).shadowWork);
}

// Translucent receivers (props not in the G-buffer, whose fragments take
// their own V) in a light's view with only opaque casters: auto gives the
// light the TranslucentCasters rule's method (PCSS left a translucent sheet
// under an opaque ball unshadowed), vpcss requested is not turned into PCSS
// there, and a method that cannot shade them is named in the frame's note.
TEST(EffectPlanner, TranslucentReceiversInViewGetVPCSS)
{
  PlannerLight sheet = Area();
  sheet.translucentReceiversInView = true;
  PlannerLight spot = Point();
  spot.translucentReceiversInView = true;
  PlannerInput in = Scene({ sheet, spot, Area() });
  EffectPlan p = MakeEffectPlan(in);
  ExpectVPCSSSoftAndHard(p, "translucent receivers in its view", "translucent receivers in its view");
  EXPECT_EQ(p.lights[2].method, Method::PCSS);
  EXPECT_FALSE(Contains(p.reason, "translucent receivers get no shadows")) << p.reason;
  in.requested = Method::VPCSS;
  p = MakeEffectPlan(in);
  EXPECT_EQ(p.lights[0].method, Method::VPCSS);
  EXPECT_EQ(p.lights[0].reason, "requested vpcss");
  EXPECT_EQ(p.lights[2].method, Method::PCSS); // nothing translucent in its view
  in.requested = Method::PCSS;
  p = MakeEffectPlan(in);
  EXPECT_EQ(p.lights[0].method, Method::PCSS);
  EXPECT_TRUE(Contains(p.reason, "translucent receivers get no shadows from pcss")) << p.reason;
  in.requested = Method::AVSM;
  EXPECT_FALSE(Contains(MakeEffectPlan(in).reason, "translucent receivers get no shadows")) << MakeEffectPlan(in).reason;
  // the reference weighs translucent casters but shades no translucent receiver
  in.requested = Method::Reference;
  EXPECT_TRUE(Contains(MakeEffectPlan(in).reason, "translucent receivers get no shadows from reference"))
    << MakeEffectPlan(in).reason;
}

// Which translucent casters are "in a light's view": those that can shadow
// a receiver it lights (a separating axis between their box and the hull of
// the light and the receivers proves they cannot).
TEST(EffectPlanner, CastersMayShadowReceivers)
{
  const LightFrame light = MakeRectLightFrame({ 0, 0, 5 }, { 0, 0, -1 }, { 0, 1, 0 }, { 1, 1 });
  Box receivers;
  receivers.Add({ -2, -2, 0 });
  receivers.Add({ 2, 2, 0.1 });
  Box over; // between the light and the ground
  over.Add({ -0.5, -0.5, 1 });
  over.Add({ 0.5, 0.5, 2 });
  EXPECT_TRUE(CastersMayShadow(light, over, receivers));
  Box aside = over; // far to the side: no segment from the ground to the light meets it
  aside.min.x += 20;
  aside.max.x += 20;
  EXPECT_FALSE(CastersMayShadow(light, aside, receivers));
  EXPECT_FALSE(CastersMayShadow(light, Box{}, receivers));
  EXPECT_FALSE(CastersMayShadow(light, over, Box{}));
}

namespace
{
void SetCost(PlannerInput& in, Method m, double ms)
{
  for (auto& info : in.methods)
  {
    if (info.method == m)
    {
      info.estimatedMs = ms;
    }
  }
}
}

TEST(EffectPlanner, InteractiveFramesFitTheBudget)
{
  // gears requested for an area and a point light; gears measured at 1200
  // ms a light, pcss at 30, hard at 10; budget 200 ms (ParaView's
  // interactive DesiredUpdateRate of 5 frames per second)
  PlannerInput in = Scene({ Area(), Point() });
  in.requested = Method::GEARS;
  SetCost(in, Method::GEARS, 1200.0);
  SetCost(in, Method::PCSS, 30.0);
  SetCost(in, Method::Hard, 10.0);
  // a still frame: every light gets gears, whatever it costs
  EffectPlan p = MakeEffectPlan(in);
  EXPECT_FALSE(p.interactive);
  EXPECT_FALSE(p.degraded);
  EXPECT_EQ(p.lights[0].method, Method::GEARS);
  EXPECT_EQ(p.lights[1].method, Method::GEARS);
  // interactive: the area light steps down to the soft rule's method, the
  // point light (no softness to keep) straight to the hard rule's
  in.frameBudgetMs = 200.0;
  p = MakeEffectPlan(in);
  EXPECT_TRUE(p.interactive);
  EXPECT_TRUE(p.degraded);
  EXPECT_EQ(p.lights[0].method, Method::PCSS);
  EXPECT_EQ(p.lights[0].stillMethod, Method::GEARS);
  EXPECT_EQ(p.lights[1].method, Method::Hard);
  EXPECT_DOUBLE_EQ(p.estimatedMs, 40.0);
  EXPECT_TRUE(Contains(p.lights[0].reason, "interactive frame (budget 200 ms): gears takes ~1200 ms, pcss stands in"))
    << p.lights[0].reason;
  EXPECT_TRUE(Contains(p.lights[0].reason, "the still frame uses gears")) << p.lights[0].reason;
  EXPECT_TRUE(Contains(p.reason, "faster methods stand in")) << p.reason;
  EXPECT_EQ(p.Summary(), "pcss, hard (interactive: stands in for gears)");
  const std::string j = p.ToJSON();
  EXPECT_TRUE(Contains(j, "\"interactive\": true, \"degraded\": true")) << j;
  EXPECT_TRUE(Contains(j, "\"frame_budget_ms\": 200")) << j;
  EXPECT_TRUE(Contains(j, "\"still_method\": \"gears\"")) << j;
  // only as far down as needed, the largest saving first: the point light's
  // step to hard (saves 1190 ms, loses no softness) before the area light's
  in.frameBudgetMs = 1250.0;
  p = MakeEffectPlan(in);
  EXPECT_EQ(p.lights[0].method, Method::GEARS);
  EXPECT_EQ(p.lights[1].method, Method::Hard) << p.lights[1].reason;
  in.frameBudgetMs = 1210.0; // gears + hard = 1210 fits exactly
  p = MakeEffectPlan(in);
  EXPECT_EQ(p.lights[0].method, Method::GEARS);
  in.frameBudgetMs = 1209.0;
  p = MakeEffectPlan(in);
  EXPECT_EQ(p.lights[0].method, Method::PCSS);
  // a budget that fits as requested changes nothing, and says so
  in.frameBudgetMs = 5000.0;
  p = MakeEffectPlan(in);
  EXPECT_TRUE(p.interactive);
  EXPECT_FALSE(p.degraded);
  EXPECT_EQ(p.lights[0].method, Method::GEARS);
  EXPECT_EQ(p.lights[1].method, Method::GEARS);
  EXPECT_TRUE(Contains(p.reason, "fits")) << p.reason;
  // nothing fits: the cheapest chain end is used (hard shadows, not none)
  in.frameBudgetMs = 1.0;
  p = MakeEffectPlan(in);
  EXPECT_EQ(p.lights[0].method, Method::Hard);
  EXPECT_EQ(p.lights[1].method, Method::Hard);
  // a stand-in dearer than the method asked for is skipped, not taken
  PlannerInput d = Scene({ Area() });
  d.requested = Method::Reference;
  SetCost(d, Method::Reference, 80.0);
  SetCost(d, Method::PCSS, 180.0);
  SetCost(d, Method::Hard, 20.0);
  d.frameBudgetMs = 50.0;
  p = MakeEffectPlan(d);
  EXPECT_EQ(p.lights[0].method, Method::Hard) << p.lights[0].reason;
  d.frameBudgetMs = 10.0; // even hard shadows do not fit: they are the fastest there is
  p = MakeEffectPlan(d);
  EXPECT_EQ(p.lights[0].method, Method::Hard);
  EXPECT_TRUE(Contains(p.reason, "still over")) << p.reason;
  // an unmeasured method runs (and is measured): the planner cannot know its cost
  PlannerInput u = Scene({ Area() });
  u.requested = Method::Reference;
  u.frameBudgetMs = 200.0;
  p = MakeEffectPlan(u);
  EXPECT_EQ(p.lights[0].method, Method::Reference);
  EXPECT_LT(p.estimatedMs, 0.0);
  EXPECT_TRUE(Contains(p.reason, "unknown")) << p.reason;
  // the chain comes from the registry's rules, not from names
  for (auto& m : in.methods)
  {
    m.rule = m.method == Method::PVSM ? PlannerRule::SoftLights
                                      : (m.method == Method::PCSS ? PlannerRule::OnRequest : m.rule);
  }
  SetCost(in, Method::PVSM, 50.0);
  in.frameBudgetMs = 200.0;
  p = MakeEffectPlan(in);
  EXPECT_EQ(p.lights[0].method, Method::PVSM);
}

// ASM's rule (issue 21): point and spot lights get the adaptive method when
// one is registered, directional lights only when one map cannot give a
// texel per pixel; without it the uniform hard method serves them all.
TEST(EffectPlanner, AdaptiveHardShadows)
{
  PlannerLight sun;
  sun.frame = MakeDirectionalLightFrame({ 0, 0, -1 }, 0.0);
  PlannerLight wideSun = sun;
  sun.receiverTexels = 3000.0;     // < 4 x 2048
  wideSun.receiverTexels = 9000.0; // > 4 x 2048
  PlannerInput in = Scene({ Point(), sun, wideSun, Area() });
  in.methods.push_back({ Method::ASM, "asm", PlannerRule::AdaptiveHardLights, false });
  EffectPlan p = MakeEffectPlan(in);
  EXPECT_EQ(p.lights[0].method, Method::ASM);
  EXPECT_TRUE(Contains(p.lights[0].reason, "point/zero-size light: hard shadows, refined where the view needs it (ASM)"))
    << p.lights[0].reason;
  EXPECT_EQ(p.lights[1].method, Method::Hard);
  EXPECT_EQ(p.lights[2].method, Method::ASM);
  EXPECT_TRUE(Contains(p.lights[2].reason, "span 9000 texels")) << p.lights[2].reason;
  EXPECT_EQ(p.lights[3].method, Method::PCSS);
  // a bigger uniform map covers the wide sun
  in.shadowMapSize = 4096;
  EXPECT_EQ(MakeEffectPlan(in).lights[2].method, Method::Hard);
  // asm asked for on an area light: the hard shadow of its centre, and the plan says so
  in.requested = Method::ASM;
  p = MakeEffectPlan(in);
  EXPECT_EQ(p.lights[3].method, Method::ASM);
  EXPECT_TRUE(Contains(p.lights[3].reason, "hard shadow of its centre")) << p.lights[3].reason;
}

// A progressive solver still refining a still view: the frame is solved again
// instead of reused, and the plan says why; once it has converged, reuse.
TEST(EffectPlanner, StillViewRefinesWhileASolverIsRefining)
{
  PlannerInput in = Scene({ Point() });
  for (const auto& l : MakeEffectPlan(in).lights) // the last frame's methods: reuse needs the same
  {
    in.lastMethods.push_back(l.method);
  }
  in.unchangedSinceLastFrame = true;
  in.refining = "asm";
  EffectPlan p = MakeEffectPlan(in);
  EXPECT_TRUE(p.shadowWork);
  EXPECT_FALSE(p.reuse);
  EXPECT_TRUE(Contains(p.reason, "asm is still refining")) << p.reason;
  in.refining.clear();
  p = MakeEffectPlan(in);
  EXPECT_TRUE(p.reuse);
}

TEST(EffectPlanner, ReceiverTexelsAtPixelSize)
{
  // a 100 x 100 ground under a sun straight above, seen from 10 above its
  // corner: the nearest receiver point is 10 away
  Box ground;
  ground.Add(glm::dvec3(0, 0, 0));
  ground.Add(glm::dvec3(100, 100, 0));
  const LightFrame sun = MakeDirectionalLightFrame({ 0, 0, -1 }, 0.0);
  const double angle = 1e-3; // radians per pixel
  EXPECT_NEAR(ReceiverTexelsAtPixelSize(sun, ground, glm::dvec3(0, 0, 10), angle, 0.0), 100.0 / (10 * angle), 1e-6);
  // from 1000 away the pixels are 100 times larger
  EXPECT_NEAR(ReceiverTexelsAtPixelSize(sun, ground, glm::dvec3(50, 50, 1000), angle, 0.0), 100.0 / (1000 * angle),
    1e-6);
  // parallel projection: its pixel size
  EXPECT_NEAR(ReceiverTexelsAtPixelSize(sun, ground, glm::dvec3(0, 0, 10), 0.0, 0.5), 200.0, 1e-9);
  EXPECT_EQ(ReceiverTexelsAtPixelSize(MakePointLightFrame({ 0, 0, 5 }), ground, glm::dvec3(0, 0, 10), angle, 0.0), 0.0);
  EXPECT_TRUE(NeedsAdaptiveMap(100.0 / (10 * angle), 2048));
  EXPECT_FALSE(NeedsAdaptiveMap(100.0 / (1000 * angle), 2048));
}

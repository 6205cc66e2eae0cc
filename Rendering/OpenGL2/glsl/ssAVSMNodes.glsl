// AVSM node arithmetic on the GPU (pasted into ssAVSMBuildCS.glsl where it
// says //SS::AVSMNodes). Step by step the same as Rendering/Core/ssAVSM.cxx
// (AVSMFunction: Insert, Compress, Evaluate, EvaluateFront, RemovalArea),
// which the unit tests check: Salvi et al. 2010 §4, a piecewise-linear
// transmittance of at most AVSM_N nodes, a thin layer as a vertical drop
// (two nodes at one depth), a segment as a linear fall, the step to 0 of an
// opaque surface, and removal of the interior node of least area.
// AVSM_N (nodes) and AVSM_C (1 or 3 channels) are defined by the host.

float nd[AVSM_N + 2]; // node depths, sorted
vec3 nt[AVSM_N + 2];  // transmittance at and behind each node
int nn = 0;           // nodes in use
float td[AVSM_N + 2]; // scratch for the insertion
vec3 tt[AVSM_N + 2];

vec3 avsmFactor(float d, float a, float b, vec3 tau)
{
  if (d < a)
  {
    return vec3(1.0);
  }
  if (d >= b)
  {
    return tau;
  }
  float s = (d - a) / (b - a);
  return vec3(1.0) + (tau - vec3(1.0)) * s;
}

// The function at z; `front`: the value just in front of z (a drop at z
// not yet taken).
vec3 nodesEval(float z, bool front)
{
  int i = -1;
  for (int k = 0; k < nn; ++k)
  {
    i = (front ? nd[k] < z : nd[k] <= z) ? k : i;
  }
  if (i < 0)
  {
    return vec3(1.0);
  }
  if (i == nn - 1)
  {
    return nt[i];
  }
  float s = (z - nd[i]) / (nd[i + 1] - nd[i]);
  return nt[i] + (nt[i + 1] - nt[i]) * s;
}

float nodesArea(int i)
{
  float area = 0.0;
  for (int c = 0; c < AVSM_C; ++c)
  {
    area += 0.5 * abs((nd[i] - nd[i - 1]) * (nt[i + 1][c] - nt[i - 1][c]) -
                      (nd[i + 1] - nd[i - 1]) * (nt[i][c] - nt[i - 1][c]));
  }
  return area;
}

void nodesCompress()
{
  while (nn > AVSM_N)
  {
    int best = 1;
    float bestArea = nodesArea(1);
    for (int i = 2; i + 1 < nn; ++i)
    {
      float a = nodesArea(i);
      if (a < bestArea)
      {
        bestArea = a;
        best = i;
      }
    }
    for (int i = best; i + 1 < nn; ++i)
    {
      nd[i] = nd[i + 1];
      nt[i] = nt[i + 1];
    }
    --nn;
  }
}

bool allZero(vec3 t)
{
  return (AVSM_C == 1) ? t.x <= 0.0 : (t.x <= 0.0 && t.y <= 0.0 && t.z <= 0.0);
}

// A blocker from a to b (a == b: a thin layer) of transmittance tau.
void nodesInsert(float a, float b, vec3 tau)
{
  // behind every node (the resolve's usual case: sorted input): the general
  // insertion below gives exactly these nodes, without its loops
  if (nn == 0 || a > nd[nn - 1])
  {
    vec3 tc = clamp(tau, 0.0, 1.0);
    if (AVSM_C == 1)
    {
      tc = vec3(tc.x);
    }
    bool passes = (AVSM_C == 1) ? tc.x >= 1.0 : (tc.x >= 1.0 && tc.y >= 1.0 && tc.z >= 1.0);
    if (passes || !(a == a) || !(b == b))
    {
      return;
    }
    vec3 last = (nn > 0) ? nt[nn - 1] : vec3(1.0);
    if (nn > 0 && allZero(last))
    {
      return; // nothing passes any more
    }
    nd[nn] = a;
    nt[nn++] = last;
    nd[nn] = (b > a) ? b : a;
    nt[nn++] = last * tc; // a zero here is the last node, as the cut below would leave it
    nodesCompress();
    return;
  }
  tau = clamp(tau, 0.0, 1.0);
  if (AVSM_C == 1)
  {
    tau = vec3(tau.x);
  }
  bool passes = (AVSM_C == 1) ? tau.x >= 1.0 : (tau.x >= 1.0 && tau.y >= 1.0 && tau.z >= 1.0);
  if (passes || !(a == a) || !(b == b))
  {
    return;
  }
  bool thin = !(b > a);
  b = thin ? a : b;
  vec3 front = nodesEval(a, true);
  vec3 atB = thin ? front * tau : nodesEval(b, false) * tau;
  int m = 0;
  bool haveA = false, haveB = false;
  for (int i = 0; i < nn; ++i)
  {
    if (!haveA && nd[i] >= a)
    {
      td[m] = a;
      tt[m++] = front;
      haveA = true;
      if (thin)
      {
        td[m] = b;
        tt[m++] = atB;
        haveB = true;
      }
    }
    if (!haveB && nd[i] > b)
    {
      td[m] = b;
      tt[m++] = atB;
      haveB = true;
    }
    td[m] = nd[i];
    tt[m++] = nt[i] * avsmFactor(nd[i], a, b, tau);
  }
  if (!haveA)
  {
    td[m] = a;
    tt[m++] = front;
  }
  if (!haveB)
  {
    td[m] = b;
    tt[m++] = atB;
  }
  nn = m;
  for (int i = 0; i < m; ++i)
  {
    nd[i] = td[i];
    nt[i] = tt[i];
    if (allZero(tt[i]))
    {
      nn = i + 1; // nothing passes behind it
      break;
    }
  }
  nodesCompress();
}

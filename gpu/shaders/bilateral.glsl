// Shared by bilateral.frag and peers.frag (pasted by #include "bilateral.glsl"): the normal
// similarity of SPEC §4, mirrors cpu_ref/bilateral.cpp: normalSimilarity.
// max(N_p·N_q, 0)^p by repeated squaring when p is whole, as the host does.
float normalSimilarity(float cosine, float power) {
  int whole = int(power);
  if (float(whole) != power || whole < 0 || whole > 64) return pow(cosine, power);
  float r = 1.0, base = cosine;
  for (int e = whole; e > 0; e >>= 1) {
    if ((e & 1) != 0) r *= base;
    base *= base;
  }
  return r;
}

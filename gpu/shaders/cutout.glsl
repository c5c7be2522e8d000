// Alpha cutouts (docs/spec.md §1.1), pasted where a shader says #include "cutout.glsl":
// gbuffer.frag and shadowmap.frag's map. Mirrors common/scene.cpp: cutoutTexel and
// Cutout::opaqueAt; the opaque bits come from the host (Scene::cutouts), so both paths read the
// same texels. The uniforms are set per mesh by gpu/gbuffer.cpp: bindCutout.
uniform int hasCutout;    // 0: the mesh is opaque
uniform sampler2D cutout; // R8: 1 where the texel is opaque
uniform ivec2 cutoutWrap; // wrapS, wrapT: 0 repeat, 1 clamp, 2 mirror (common/scene.h: Wrap)

// i mod n for n > 0, in [0, n) (GLSL's % is undefined for negative operands).
int positiveModulo(int i, int n) {
  int r = (i < 0 ? -i : i) % n;
  return i < 0 && r != 0 ? n - r : r;
}

// The texel index along one axis of n texels for texture coordinate t, nearest.
int cutoutTexel(float t, int n, int wrap) {
  // 1. the texel holding t·n, as a whole number kept well inside int's range
  int i = int(clamp(floor(t * float(n)), -16777216.0, 16777216.0));
  // 2. wrapped into [0, n)
  if (wrap == 1) return clamp(i, 0, n - 1);
  if (wrap == 2) {
    int k = positiveModulo(i, 2 * n);  // period 2n: forward, then backward
    return k < n ? k : 2 * n - 1 - k;
  }
  return positiveModulo(i, n);
}

// Whether the surface at texture coordinate st is a hole in its mesh's cutout.
bool transparentAt(vec2 st) {
  if (hasCutout == 0) return false;
  ivec2 size = textureSize(cutout, 0);
  ivec2 texel = ivec2(cutoutTexel(st.x, size.x, cutoutWrap.x), cutoutTexel(st.y, size.y, cutoutWrap.y));
  return texelFetch(cutout, texel, 0).r < 0.5;
}

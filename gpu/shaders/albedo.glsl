// Base-colour textures (docs/spec.md §1.2), pasted where gbuffer.frag says #include "albedo.glsl"
// (after cutout.glsl, whose cutoutTexel addresses the texel). Mirrors common/scene.cpp:
// ColorTexture::linearAt and Mesh::albedoAt: the texel's stored sRGB bytes, decoded through the
// host's table (srgbToLinearTable), times the factor, in float32. The uniforms are set per mesh
// by gpu/gbuffer.cpp: bindColorTexture.
uniform int hasTexture;          // 0: the factor alone
uniform sampler2D baseColor;     // RGBA8: the image's bytes as stored (sRGB), read back as byte/255
uniform sampler2D srgbToLinear;  // 256x1 R32F: the host's table, byte -> linear
uniform ivec2 textureWrap;       // wrapS, wrapT: 0 repeat, 1 clamp, 2 mirror (common/scene.h: Wrap)

// The linear value of one stored byte b/255 (exact: b/255 in float times 255 rounds back to b).
float linearOf(float stored) {
  return texelFetch(srgbToLinear, ivec2(int(stored * 255.0 + 0.5), 0), 0).r;
}

// The albedo at texture coordinate st: factor × the texel's linear RGB.
vec3 albedoAt(vec3 factor, vec2 st) {
  if (hasTexture == 0) return factor;
  ivec2 size = textureSize(baseColor, 0);
  ivec2 texel = ivec2(cutoutTexel(st.x, size.x, textureWrap.x), cutoutTexel(st.y, size.y, textureWrap.y));
  vec4 stored = texelFetch(baseColor, texel, 0);
  return factor * vec3(linearOf(stored.r), linearOf(stored.g), linearOf(stored.b));
}

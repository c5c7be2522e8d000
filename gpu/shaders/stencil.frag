#version 330 core
// Fills the stencil buffer from S_ℓ (SPEC §4): fragments where S = 0 are discarded, the rest
// write the stencil reference. The effect passes then run with the stencil test, so masked
// fragments are never shaded.
uniform sampler2D stencilMask;
void main() {
  if (texelFetch(stencilMask, ivec2(gl_FragCoord.xy), 0).r < 0.5) discard;
}

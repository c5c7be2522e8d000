#version 330 core
// The light's shadow map and its one-tap test (SPEC §2 shadow edges, §6 SSM), mirrors
// cpu_ref/shadowmap.cpp. Two variants of this file:
//  - default: the rasterised map (renderShadowMap): the distance from the light plane to the
//    nearest surface at each texel centre; texels no surface covers keep the clear, kNoBlocker.
//  - SHADOW_TEST: shadowTestImage, the one-tap test at every pixel of the level-0 G-buffer
//    (1 lit, 0 shadowed; background 1).
#ifdef SHADOW_TEST
#include "shadowmap.glsl"
uniform sampler2D positionHit;  // G-buffer L0: view position, hit
uniform sampler2D normalDepth;  // G-buffer L0: view normal, depth
layout(location = 0) out vec4 lit;
void main() {
  ivec2 pixel = ivec2(gl_FragCoord.xy);
  vec4 ph = texelFetch(positionHit, pixel, 0);
  if (ph.w < 0.5) {
    lit = vec4(1.0);
    return;
  }
  vec3 n = texelFetch(normalDepth, pixel, 0).xyz;
  Receiver r = receiverAt(viewToWorld(ph.xyz), viewDirectionToWorld(n));
  lit = vec4(shadowTest(r), 0.0, 0.0, 1.0);
}
#else
#include "cutout.glsl"
in float lightDepth;
in vec2 surfaceTexcoord;
layout(location = 0) out vec4 depth;  // R32F target: only .r is kept
void main() {
  if (transparentAt(surfaceTexcoord)) discard;  // alpha cutout: the ray from the light goes on
  depth = vec4(lightDepth, 0.0, 0.0, 1.0);
}
#endif

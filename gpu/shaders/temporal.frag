#version 330 core
// SPEC §14, the temporal term, mirrors cpu_ref/temporal.cpp step by step (the same float32
// operations in the same order): where the previous frame shows the same surface, a pixel served
// by the coarser levels keeps λ (1 − α_0) of its reprojected result. One pass over W×H
// (gpu/temporal.cpp drawTemporal); CHANNELS is the effect's (1 or 3).
uniform sampler2D positionHit;          // G-buffer L0: view position, hit in w
uniform sampler2D normalDepth;          // G-buffer L0: view normal, depth
uniform sampler2D stencil0;             // S_0
uniform sampler2D alpha0;               // a_0
uniform sampler2D blended;              // the blend's final image c (W×H)
uniform sampler2D previousResult;       // the previous frame's result (W×H)
uniform sampler2D previousNormalDepth;  // the previous frame's view normal (rgb) and depth (a), W×H
uniform vec3 row0, row1, row2;          // R: this view space → the previous one (host, common/temporal.h)
uniform vec3 offset;                    // t
uniform vec3 previousProjection;        // the previous view's cx, cy and focal
uniform float lambda;                   // λ
uniform float weight0;                  // w_0
uniform float depthTolerance;           // δ
uniform float normalCos;                // κ
layout(location = 0) out vec4 result;   // final'
layout(location = 1) out vec4 history;  // h in rgb, λ_p in a

float rowTimes(vec3 r, vec3 v) { return r.x * v.x + r.y * v.y + r.z * v.z; }

void main() {
  ivec2 p = ivec2(gl_FragCoord.xy);
  ivec2 size = textureSize(previousResult, 0);
  vec3 c = texelFetch(blended, p, 0).rgb;
  vec3 h = vec3(0.0);
  float weight = 0.0;
  vec4 ph = texelFetch(positionHit, p, 0);
  if (ph.w > 0.5) {
    // 1. p' = R p + t, n' = R n; z' = −p'.z; q = (cx + f p'.x / z', cy − f p'.y / z')
    vec3 pos = ph.xyz, n = texelFetch(normalDepth, p, 0).xyz;
    vec3 pp = vec3(rowTimes(row0, pos) + offset.x, rowTimes(row1, pos) + offset.y, rowTimes(row2, pos) + offset.z);
    float z = -pp.z;
    if (z > 0.0) {
      vec2 q = vec2(previousProjection.x + previousProjection.z * pp.x / z,
                    previousProjection.y - previousProjection.z * pp.y / z);
      vec3 np = vec3(rowTimes(row0, n), rowTimes(row1, n), rowTimes(row2, n));
      // 2. the bilinear taps around q, pixel centres at the integers of u = q − ½
      float ux = q.x - 0.5, uy = q.y - 0.5;
      float fx0 = floor(ux), fy0 = floor(uy);
      float fx = ux - fx0, fy = uy - fy0;
      bool near = abs(fx0) < 1.0e8 && abs(fy0) < 1.0e8;
      ivec2 t0 = near ? ivec2(int(fx0), int(fy0)) : ivec2(-2);
      vec2 wx = vec2(1.0 - fx, fx), wy = vec2(1.0 - fy, fy);
      for (int k = 0; k < 4; ++k) {
        int i = k & 1, j = k >> 1;
        ivec2 t = t0 + ivec2(i, j);
        float w = wx[i] * wy[j];
        if (!near || t.x < 0 || t.y < 0 || t.x >= size.x || t.y >= size.y) continue;
        // 3. on geometry, the same depth within δ z' and the same facing within κ
        vec4 nd = texelFetch(previousNormalDepth, t, 0);
        if (!(nd.w > 0.0)) continue;
        if (!(abs(nd.w - z) <= depthTolerance * z)) continue;
        if (!(nd.x * np.x + nd.y * np.y + nd.z * np.z >= normalCos)) continue;
        // 4. the taps that show the same surface, their weights normalised
        weight += w;
        h += w * texelFetch(previousResult, t, 0).rgb;
      }
      if (weight > 0.0) h = h / weight;
    }
  }
  // 5. λ_p = λ (1 − α_0) where the history has a sample; α_0 = S_0 ? min(a_0 w_0, 1) : 0
  float a0 = texelFetch(stencil0, p, 0).r > 0.5 ? min(texelFetch(alpha0, p, 0).r * weight0, 1.0) : 0.0;
  float lambdaP = weight > 0.0 ? lambda * (1.0 - a0) : 0.0;
  // 6. final' = c + λ_p (h − c)
  vec3 blendedResult = lambdaP > 0.0 ? c + lambdaP * (h - c) : c;
  result = vec4(blendedResult, 1.0);
  history = vec4(h, lambdaP);
}

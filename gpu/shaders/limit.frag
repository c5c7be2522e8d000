#version 330 core
// SPEC §13 — the level limit (foveation and motion), mirrors cpu_ref/foveation.cpp, at every
// pixel of the padded full-res grid. Steps as there:
//   1. eccentricity e = d / ppd (eccentricityAt)
//   2. what the eye allows: the largest l with d² ≥ radius2[l] (foveationLevel), integers
//   3. motion v: the surface point projected by the previous view, less the pixel centre (motionAt)
//   4. what motion allows: the largest l ≤ motionCap with |v|² ≥ speed2[l] (motionLevel)
//   5. the limit: min(coarsest, max(fovea, motion))
// Output (RGBA32F): e, |v|, fovea + kLevelCount · motion (= 4 · motion), the limit.
uniform sampler2D positionHit;  // G-buffer L0: view position, hit
uniform int gaze, foveate, motion;  // 0/1
uniform ivec2 gazePixel;
uniform float ppd;
uniform int radius2[kLevelCount];
uniform float speed2[kLevelCount];
uniform int motionCap, coarsest;
uniform float motionScale;
uniform vec3 viewEye, viewRight, viewUp, viewForward;  // this frame's View
uniform vec3 prevEye, prevRight, prevUp, prevForward;  // the previous frame's View
uniform float prevFocal, prevCx, prevCy;
layout(location = 0) out vec4 result;

// kLevelCount, kMotionBehind (a point behind the previous camera moves this fast):
// common/shader_constants.h

void main() {
  ivec2 p = ivec2(gl_FragCoord.xy);
  float e = 0.0, speed = 0.0;
  int fovea = 0, moving = 0;
  if (gaze != 0) {
    // 1. eccentricity
    ivec2 d = p - gazePixel;
    int d2 = d.x * d.x + d.y * d.y;
    e = sqrt(float(d2)) / ppd;
    // 2. what the eye allows
    if (foveate != 0)
      for (int l = 1; l < kLevelCount; ++l)
        if (d2 >= radius2[l]) fovea = l;
  }
  if (motion != 0) {
    // 3. motion
    vec4 ph = texelFetch(positionHit, p, 0);
    vec2 v = vec2(0.0);
    if (ph.w >= 0.5) {
      vec3 world = viewEye + (viewRight * ph.x + viewUp * ph.y - viewForward * ph.z);
      vec3 w = world - prevEye;
      vec3 q = vec3(dot(w, prevRight), dot(w, prevUp), -dot(w, prevForward));
      if (!(-q.z > 0.0)) {
        v = vec2(kMotionBehind);
      } else {
        float z = -q.z;
        vec2 s = vec2(prevCx + prevFocal * q.x / z, prevCy - prevFocal * q.y / z);
        vec2 dv = s - (vec2(p) + 0.5);
        v = vec2(motionScale * dv.x, motionScale * dv.y);
      }
    }
    speed = v.x == kMotionBehind ? kMotionBehind : sqrt(v.x * v.x + v.y * v.y);
    // 4. what motion allows
    float v2 = v.x * v.x + v.y * v.y;
    for (int l = 1; l < kLevelCount; ++l)
      if (l <= motionCap && v2 >= speed2[l]) moving = l;
  }
  // 5. the limit
  int limit = min(coarsest, max(fovea, moving));
  result = vec4(e, speed, float(fovea + kLevelCount * moving), float(limit));
}

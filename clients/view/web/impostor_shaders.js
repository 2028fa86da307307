// The impostors' shaders (impostors.js draws with them): each body one quad, posed in the vertex
// shader from the pose texture, its true shape ray-cast in the fragment shader.
// (GLSL in JavaScript strings: three.js compiles them, and the page's modules load without a
// bundler or a fetch of their own.)

import { kOctantShade } from './stage.js';

// Texels per row of the pose texture; a body takes two (p_WBo, placed) and (q_WB as x, y, z, w),
// side by side in one row because the width is even.
export const kPoseWidth = 1024;

// Impostors: each body one screen-facing quad (4 vertices instead of its mesh's 24-60) whose
// fragment shader intersects the view ray with the body's true shape, in the shape's frame U
// (box: slab test; ellipsoid: quadratic; cylinder: quadratic and two planes; capsule: quadratic
// and two spheres), discards misses, shades the hit by its normal and writes its depth, so that
// bodies occlude and cut through each other as meshes do. Why: meshes merged into one draw cost
// SwiftShader per vertex (24-60 a body, two texture fetches each), impostors per pixel, which the
// dynamic resolution lowers (bench/notes/view.md). Shading: Lambert per pixel, the light of the
// page's hemisphere (sky white, ground 0x404040, intensity 2, about z) plus its sun (1.5 from
// (3, -2, 5)), times the BRDF colour / pi, as three.js's MeshLambertMaterial computes it, the
// colour darker on alternate octants of U (stage.js: the markings that show a body's spin).
// The quad lies in the plane through Bo facing the camera, its half-sizes along the screen's axes
// the shape's support (its half-width along that axis, for any orientation), grown by d / (d - s)
// for the part of the body nearer the camera than that plane (d: Bo's distance from the camera,
// s: the support towards it): it covers the body's projection, and mostly not much more. The ray
// is taken from the quad's point (p in U, near the body: float32 keeps the quadratics precise),
// along the camera's ray through it; at its parameter t = -1 it is at the camera.
// Per vertex: the body's slot, its shape's half-extents in U (box: half its edges; ellipsoid: its
// radii; cylinder: radius, radius, half its length; capsule: radius, radius, half its whole
// length, along z) and q_BU; the quad's corner is gl_VertexID's lowest two bits.
export const kImpostorVertex = `
uniform highp sampler2D bodyPoses;
attribute float bodySlot;
attribute vec3 extent;
attribute vec4 shapeFrame;
attribute vec3 color;
flat varying vec3 vExtent;
flat varying vec3 vColor;
flat varying vec3 vCamera;         // the camera's position from Bo, in U
flat varying vec3 vUp;             // the hemisphere light's axis (z of W) in U
flat varying vec3 vSun;            // towards the sun, in U
varying vec3 vPoint;               // the quad's point in U
vec3 rotateByQuaternion(vec4 q, vec3 v) { return v + 2.0 * cross(q.xyz, cross(q.xyz, v) + q.w * v); }
vec4 quaternionProduct(vec4 a, vec4 b) {
  return vec4(a.w * b.xyz + b.w * a.xyz + cross(a.xyz, b.xyz), a.w * b.w - dot(a.xyz, b.xyz));
}
// The shape's half-width along the unit direction n (in U).
float support(vec3 n) {
#if defined(SHAPE_BOX)
  return dot(extent, abs(n));
#elif defined(SHAPE_ELLIPSOID)
  return length(extent * n);
#elif defined(SHAPE_CYLINDER)
  return extent.z * abs(n.z) + extent.x * length(n.xy);
#else
  return (extent.z - extent.x) * abs(n.z) + extent.x;
#endif
}
void main() {
  int poseTexel = 2 * int(bodySlot + 0.5);
  ivec2 poseAt = ivec2(poseTexel % ${kPoseWidth}, poseTexel / ${kPoseWidth});
  vec4 bodyP = texelFetch(bodyPoses, poseAt, 0);
  vec4 q_UW = quaternionProduct(texelFetch(bodyPoses, poseAt + ivec2(1, 0), 0), shapeFrame);
  q_UW.xyz = -q_UW.xyz;  // the inverse: W to U
  vec3 toCamera = cameraPosition - bodyP.xyz;
  float d = length(toCamera);
  vec3 w = toCamera / d;
  vec3 u = normalize(cross(vec3(viewMatrix[0][1], viewMatrix[1][1], viewMatrix[2][1]), w));
  vec3 v = cross(w, u);
  vec3 uU = rotateByQuaternion(q_UW, u), vU = rotateByQuaternion(q_UW, v);
  float nearer = support(rotateByQuaternion(q_UW, w));
  // Not placed, or the camera within the body's reach: outside the clip volume, nothing drawn.
  if (bodyP.w == 0.0 || d <= nearer) {
    gl_Position = vec4(0.0, 0.0, 2.0, 1.0);
    return;
  }
  vec2 corner = vec2(float(gl_VertexID & 1), float((gl_VertexID >> 1) & 1)) * 2.0 - 1.0;
  vec2 reach = (d / (d - nearer)) * corner * vec2(support(uU), support(vU));
  gl_Position = projectionMatrix * viewMatrix * vec4(bodyP.xyz + reach.x * u + reach.y * v, 1.0);
  vPoint = reach.x * uU + reach.y * vU;
  vCamera = rotateByQuaternion(q_UW, toCamera);
#if defined(SHAPE_ELLIPSOID)
  // An ellipsoid's ray in the frame where it is the unit sphere.
  vPoint /= extent;
  vCamera /= extent;
#endif
  vUp = rotateByQuaternion(q_UW, vec3(0.0, 0.0, 1.0));
  vSun = rotateByQuaternion(q_UW, vec3(0.4867, -0.3244, 0.8111));
  vExtent = extent;
  vColor = color;
}
`;
export const kImpostorFragment = `
uniform mat4 projectionMatrix;
uniform float opacity;
flat varying vec3 vExtent;
flat varying vec3 vColor;
flat varying vec3 vCamera;
flat varying vec3 vUp;
flat varying vec3 vSun;
varying vec3 vPoint;
void main() {
  // The ray p + t dir in U (ellipsoid: scaled to the unit sphere), dir from the camera through p.
  vec3 p = vPoint, dir = vPoint - vCamera, e = vExtent;
  float t;
  vec3 n;
#if defined(SHAPE_BOX)
  vec3 inverse = 1.0 / dir, t0 = (-e - p) * inverse, t1 = (e - p) * inverse;
  vec3 enter = min(t0, t1), leave = max(t0, t1);
  t = max(max(enter.x, enter.y), enter.z);
  if (t > min(min(leave.x, leave.y), leave.z)) discard;
  n = -sign(dir) * vec3(equal(enter, vec3(t)));
#elif defined(SHAPE_ELLIPSOID)
  float a = dot(dir, dir), b = dot(p, dir), disc = b * b - a * (dot(p, p) - 1.0);
  if (disc < 0.0) discard;
  t = (-b - sqrt(disc)) / a;
  n = normalize((p + t * dir) / e);
#else
  // The side: (p.xy + t dir.xy)^2 = r^2 (a ray along the axis: a tiny a, roots far apart).
  float r = e.x, a = max(dot(dir.xy, dir.xy), 1e-12), b = dot(p.xy, dir.xy);
  float disc = b * b - a * (dot(p.xy, p.xy) - r * r);
  if (disc < 0.0) discard;
  float root = sqrt(disc);
  t = (-b - root) / a;
#if defined(SHAPE_CYLINDER)
  // Within the slab |z| <= e.z too: the later entry, if before the earlier exit.
  float t0 = (-e.z - p.z) / dir.z, t1 = (e.z - p.z) / dir.z;
  float capEnter = min(t0, t1);
  if (max(t, capEnter) > min((-b + root) / a, max(t0, t1))) discard;
  n = t > capEnter ? vec3((p.xy + t * dir.xy) / r, 0.0) : vec3(0.0, 0.0, -sign(dir.z));
  t = max(t, capEnter);
#else
  // Entering the infinite cylinder beyond an end, the ray meets that end's sphere or nothing.
  float h = e.z - r, z = p.z + t * dir.z;
  vec3 hit = p + t * dir;
  n = vec3(hit.xy / r, 0.0);
  if (abs(z) > h) {
    vec3 pc = p - vec3(0.0, 0.0, sign(z) * h);
    float a3 = dot(dir, dir), b3 = dot(pc, dir), disc3 = b3 * b3 - a3 * (dot(pc, pc) - r * r);
    if (disc3 < 0.0) discard;
    t = (-b3 - sqrt(disc3)) / a3;
    n = (pc + t * dir) / r;
  }
#endif
#endif
  // Behind the camera (t = -1 is the camera): not seen.
  if (t <= -1.0) discard;
  // The hit's depth: in the camera's frame (1 + t) times the quad point's, -1 / w.
  float viewZ = -(1.0 + t) / gl_FragCoord.w;
  gl_FragDepth = 0.5 * (projectionMatrix[2][2] * viewZ + projectionMatrix[3][2]) / -viewZ + 0.5;
  vec3 irradiance = 2.0 * mix(vec3(0.0513), vec3(1.0), 0.5 * dot(n, vUp) + 0.5) +
                    1.5 * max(dot(n, vSun), 0.0);
  // The octant markings (stage.js): the hit in U, whose octants are the body's.
  vec3 mark = p + t * dir;
  float shade = mark.x * mark.y * mark.z < 0.0 ? ${kOctantShade.toFixed(3)} : 1.0;
  gl_FragColor = vec4(vColor * shade * irradiance * 0.3183098861837907, opacity);
  #include <colorspace_fragment>
}
`;

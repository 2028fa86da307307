// The stage the bodies are drawn on: a background that darkens towards the bottom, the grid of
// the x-y plane, the world axes, the lights, and the markings that make a body's turning visible.
//
// The grid is drawn first and writes no depth, so that nothing it crosses is hidden by it: the
// world axes lie in its plane (two of them along its lines), and depth-tested against it they
// flickered in and out (z-fighting). The axes are solid arrows (x red, y green, z blue), 1 m long.
//
// Markings: every body is shaded darker on alternate octants of its own frame (the sign of
// x y z, in the frame its shape is drawn in), so that a sphere or a cylinder turning about its
// axis, which a uniform colour hides, shows its spin. The impostors' shader does the same
// (impostor_shaders.js, kOctantShade).
import * as THREE from 'three';

export const kOctantShade = 0.5;  // the darker octants' albedo, times the body's colour

export function makeStage(scene) {
  scene.background = gradientTexture(0x2b3139, 0x121418);
  const grid = new THREE.GridHelper(10, 20, 0x7a808a, 0x3c4048);
  grid.rotation.x = Math.PI / 2;  // the x-y plane
  grid.material.depthWrite = false;
  grid.renderOrder = -1;
  scene.add(grid);
  const axes = worldAxes();
  scene.add(axes);
  // (The impostors' shader has these two lights written in: impostor_shaders.js.)
  scene.add(new THREE.HemisphereLight(0xffffff, 0x404040, 2.0));
  const sun = new THREE.DirectionalLight(0xffffff, 1.5);
  sun.position.set(3, -2, 5);
  scene.add(sun);
  return { grid, axes };
}

// Arrows along W's axes from its origin: x red, y green, z blue, 1 m.
function worldAxes() {
  const group = new THREE.Group();
  group.name = 'world axes';
  const shaft = new THREE.CylinderGeometry(0.012, 0.012, 0.88, 12);
  shaft.translate(0, 0.44, 0);
  const head = new THREE.ConeGeometry(0.035, 0.12, 16);
  head.translate(0, 0.94, 0);
  const toward = [new THREE.Vector3(1, 0, 0), new THREE.Vector3(0, 1, 0), new THREE.Vector3(0, 0, 1)];
  [0xe53935, 0x43a047, 0x1e88e5].forEach((color, k) => {
    const material = new THREE.MeshBasicMaterial({ color });
    const arrow = new THREE.Group();
    arrow.add(new THREE.Mesh(shaft, material), new THREE.Mesh(head, material));
    arrow.quaternion.setFromUnitVectors(new THREE.Vector3(0, 1, 0), toward[k]);  // three's y -> axis
    group.add(arrow);
  });
  return group;
}

// A vertical gradient from `top` to `bottom`, as the scene's background (fills the view).
function gradientTexture(top, bottom) {
  const canvas = document.createElement('canvas');
  canvas.width = 2;
  canvas.height = 256;
  const g = canvas.getContext('2d');
  const fill = g.createLinearGradient(0, 0, 0, canvas.height);
  fill.addColorStop(0, `#${new THREE.Color(top).getHexString()}`);
  fill.addColorStop(1, `#${new THREE.Color(bottom).getHexString()}`);
  g.fillStyle = fill;
  g.fillRect(0, 0, canvas.width, canvas.height);
  const texture = new THREE.CanvasTexture(canvas);
  texture.colorSpace = THREE.SRGBColorSpace;
  return texture;
}

// The octant markings on a mesh material drawing unit geometries (shapes.js): the fragment's
// position in the geometry's own frame (the body's, up to the shape's scale) decides its shade.
export function addMarkings(material) {
  material.onBeforeCompile = (shader) => {
    shader.vertexShader = shader.vertexShader
      .replace('#include <common>', '#include <common>\nvarying vec3 vMarkPoint;')
      .replace('#include <begin_vertex>', '#include <begin_vertex>\nvMarkPoint = position;');
    shader.fragmentShader = shader.fragmentShader
      .replace('#include <common>', '#include <common>\nvarying vec3 vMarkPoint;')
      .replace('#include <color_fragment>',
               `#include <color_fragment>\n` +
               `if (vMarkPoint.x * vMarkPoint.y * vMarkPoint.z < 0.0) diffuseColor.rgb *= ${kOctantShade.toFixed(3)};`);
  };
  material.customProgramCacheKey = () => 'octant-markings';
  return material;
}

// A scene (?scene=ID): its objects in their instance colours, the table of objects, and picking.
import {
  THREE, Viewer, fillSwatchTable, get, instanceColour, matrixFromRows, parseMesh, setTitle, showPickedRows,
} from './common.js';
import { addMountedRobot, tableDisc } from './robot.js';

function showTable(scene) {
  const table = fillSwatchTable(document.createElement('table'),
    ['object', 'label', 'mesh', 'instance', 'material', 'albedo'], scene.objects,
    (object) => `#${instanceColour(object.instance_id).getHexString()}`,
    (object) => [object.object_id, object.label, object.mesh_id, object.instance_id,
      object.material ? object.material.preset : '', object.material ? object.material.albedo : '']);
  document.getElementById('content').appendChild(table);
}

function describeMaterial(material) {
  if (!material) return '';
  const values = `albedo ${material.albedo}, metallic ${material.metallic}, roughness ${material.roughness}, ` +
    `specular ${material.specular_reflectance}`;
  return material.preset ? `${material.preset} (${values})` : values;
}

// Reports the clicked object in #picked and keeps it in window.vscanPicked (null: nothing hit).
function showPicked(object) {
  window.vscanPicked = object && {
    object_id: object.object_id, label: object.label, instance_id: object.instance_id, material: object.material,
  };
  showPickedRows(object && [['object', object.object_id], ['label', object.label],
    ['instance', String(object.instance_id)], ['material', describeMaterial(object.material)]]);
}

// Adds the scene's objects to viewer.world; returns [{object, mesh}] in the scene's order.
export async function addSceneObjects(viewer, scene) {
  const geometries = new Map();
  for (const meshId of new Set(scene.objects.map((o) => o.mesh_id))) {
    geometries.set(meshId, parseMesh(await get(`api/meshes/${encodeURIComponent(meshId)}`, 'binary')));
  }
  const placed = [];
  for (const object of scene.objects) {
    const mesh = new THREE.Mesh(geometries.get(object.mesh_id),
      new THREE.MeshLambertMaterial({ color: instanceColour(object.instance_id) }));
    mesh.matrixAutoUpdate = false;
    mesh.matrix.copy(matrixFromRows(object.world_from_object)
      .multiply(new THREE.Matrix4().makeScale(object.scale, object.scale, object.scale)));
    viewer.world.add(mesh);
    placed.push({ object, mesh });
  }
  viewer.world.updateMatrixWorld(true);
  return placed;
}

export async function showScene(id) {
  const scene = await get(`api/scenes/${encodeURIComponent(id)}`);
  setTitle(`vscan: ${scene.name || scene.scene_id} (${scene.scene_id}, revision ${scene.revision})`);
  showTable(scene);
  const viewer = new Viewer();
  const placed = await addSceneObjects(viewer, scene);
  const bounds = new THREE.Box3();
  for (const { mesh } of placed) bounds.expandByObject(mesh);
  const objectBounds = bounds.clone();
  // The scene's mounted robots at their home pose, each with its sensor's frame on the flange.
  const robots = [];
  for (const mount of scene.mounts || []) {
    const robot = await addMountedRobot(viewer, mount.mount_id);
    robot.group.updateMatrixWorld(true);
    bounds.expandByObject(robot.group);
    robots.push(robot);
  }
  if (scene.table && scene.table.enabled) {
    const onTable = placed.filter(({ object }) => object.on_table);
    const size = objectBounds.isEmpty() ? 0.1 : objectBounds.getSize(new THREE.Vector3()).length() / 2;
    viewer.world.add(tableDisc(scene.table, onTable.length ? size : 0.1));
  }
  viewer.frame(bounds);
  viewer.render();

  // A click reports the nearest object under the pointer, or that none is there.
  const meshes = placed.map(({ mesh }) => mesh);
  window.vscanPickCount = 0;
  viewer.onClick((raycaster) => {
    const [hit] = raycaster.intersectObjects(meshes);
    showPicked(hit ? placed[meshes.indexOf(hit.object)].object : null);
    viewer.markPicked(hit || null);
    window.vscanPickCount += 1;
  });

  // Where each object's bounds centre lands in the page (CSS pixels), for checks of what is drawn.
  window.vscanViewer = viewer;
  window.vscanView = {
    scene_id: scene.scene_id,
    robots: robots.map(({ pose, meshes }) => ({
      mount_id: pose.mount_id,
      link_pixels: meshes.map((mesh) => viewer.pixelOf(new THREE.Box3().setFromObject(mesh).getCenter(new THREE.Vector3()))),
      sensor_pixel: viewer.pixelOf(new THREE.Vector3().setFromMatrixPosition(matrixFromRows(pose.world_from_sensor))),
    })),
    objects: placed.map(({ object, mesh }) => {
      const colour = instanceColour(object.instance_id);
      return {
        object_id: object.object_id,
        colour: [colour.r, colour.g, colour.b].map((v) => Math.round(v * 255)),
        pixel: viewer.pixelOf(new THREE.Box3().setFromObject(mesh).getCenter(new THREE.Vector3())),
      };
    }),
  };
}

// Renders deploy/kustomize/base and every overlay with `kubectl kustomize`, validates each object
// against the Kubernetes schema (kubernetes-models, offline) and checks that the StatefulSet, its
// headless Service, the container file and vscand's measured memory fit together.
// Usage: node validate_kustomize.mjs <kubectl> <deploy/kustomize> <deploy/Containerfile>

import assert from "node:assert/strict";
import { spawnSync } from "node:child_process";
import { existsSync, readdirSync, readFileSync } from "node:fs";
import { join } from "node:path";
import { parseAllDocuments } from "yaml";
import { argAfter, expectRejected, validateAgainstSchema } from "./manifest_checks.mjs";

// tests/deploy/measure_memory.sh on the release build: four concurrent 1280x1024 scans peak at
// 314 MiB of resident memory; docs/DEPLOY.md records the run.
const MEASURED_PEAK_MIB = 314;
const MEASURED_CONCURRENT_SCANS = 4;
const MEASURED_RAYS_PER_SCAN = 1280 * 1024;
// vscand gives cancelled work this long after --grace-seconds before it exits (server/main.cpp).
const STOP_SECONDS = 5;

function render(kubectl, dir) {
  const run = spawnSync(kubectl, ["kustomize", dir], { encoding: "utf8" });
  if (run.error?.code === "ENOENT") {
    throw new Error(`${kubectl} not found: install Debian's kubernetes-client (scripts/install-deps.sh)`);
  }
  if (run.error) throw run.error;
  assert.equal(run.status, 0, `kubectl kustomize ${dir} failed:\n${run.stderr}`);
  const objects = [];
  for (const doc of parseAllDocuments(run.stdout)) {
    if (doc.errors.length > 0) throw new Error(`${dir}: ${doc.errors[0].message}`);
    if (doc.contents !== null) objects.push(doc.toJS());
  }
  return objects;
}

function mebibytes(quantity) {
  const units = { Ki: 1 / 1024, Mi: 1, Gi: 1024 };
  const match = /^(\d+)(Ki|Mi|Gi)$/.exec(quantity);
  assert.ok(match, `memory quantity ${quantity} is not in Ki, Mi or Gi`);
  return Number(match[1]) * units[match[2]];
}

function only(objects, kind) {
  const found = objects.filter((o) => o.kind === kind);
  assert.equal(found.length, 1, `expected one ${kind}, got ${found.length}`);
  return found[0];
}

function checkService(service, set) {
  assert.equal(service.spec.clusterIP, "None", "the Service must be headless so each pod has its own DNS name");
  assert.equal(set.spec.serviceName, service.metadata.name, "pod DNS names come from the StatefulSet's serviceName");
  assert.equal(service.metadata.namespace, set.metadata.namespace, "the Service and the StatefulSet share a namespace");
  const podLabels = set.spec.template.metadata.labels;
  assert.deepEqual(set.spec.selector.matchLabels, service.spec.selector);
  for (const [key, value] of Object.entries(service.spec.selector)) {
    assert.equal(podLabels[key], value, `the Service selects ${key}=${value}, which the pods lack`);
  }
  const container = set.spec.template.spec.containers[0];
  for (const port of service.spec.ports) {
    assert.ok(container.ports.some((p) => p.name === port.targetPort || p.containerPort === port.targetPort),
      `Service port ${port.name} targets ${port.targetPort}, which the container does not expose`);
  }
}

function checkServer(set, containerUid) {
  const pod = set.spec.template.spec;
  const container = pod.containers[0];
  const args = container.args;
  const listenPort = Number(argAfter(args, "--listen").split(":").pop());
  assert.ok(container.ports.some((p) => p.containerPort === listenPort), `--listen port ${listenPort} is not exposed`);
  for (const probe of ["startupProbe", "readinessProbe", "livenessProbe"]) {
    assert.ok(container[probe]?.grpc, `${probe} must ask vscand's gRPC health service`);
    assert.equal(container[probe].grpc.port, listenPort, `${probe} must probe the port vscand listens on`);
    assert.ok(!container[probe].grpc.service, `${probe}: vscand reports health for the service "" only`);
  }

  const dataDir = argAfter(args, "--data-dir");
  const mount = container.volumeMounts.find((m) => m.mountPath === dataDir);
  assert.ok(mount, `--data-dir ${dataDir} is not a volume mount`);
  const claim = set.spec.volumeClaimTemplates.find((t) => t.metadata.name === mount.name);
  assert.ok(claim, `${dataDir} must be on a volume claim template, one volume per replica`);
  assert.ok(!pod.volumes?.some((v) => v.name === mount.name), `${mount.name} is also a pod volume`);
  assert.deepEqual(claim.spec.accessModes, ["ReadWriteOnce"]);

  assert.equal(pod.securityContext.runAsUser, containerUid, "the server runs as the container file's vscan user");
  assert.equal(pod.securityContext.fsGroup, containerUid, "fsGroup makes a fresh claim writable by that user");
  assert.equal(container.securityContext.readOnlyRootFilesystem, true);
  const tmp = container.volumeMounts.find((m) => m.mountPath === "/tmp");
  assert.ok(tmp && pod.volumes.some((v) => v.name === tmp.name && v.emptyDir), "/tmp must be writable (Mesa's cache)");

  const grace = Number(argAfter(args, "--grace-seconds"));
  assert.ok(pod.terminationGracePeriodSeconds >= grace + STOP_SECONDS,
    `terminationGracePeriodSeconds ${pod.terminationGracePeriodSeconds} < --grace-seconds ${grace} + ${STOP_SECONDS}`);

  // The memory figure holds only for the scan sizes and concurrency it was measured at.
  assert.ok(Number(argAfter(args, "--max-rays")) <= MEASURED_RAYS_PER_SCAN, "--max-rays exceeds the measured scan");
  assert.ok(Number(argAfter(args, "--max-concurrent-scans")) <= MEASURED_CONCURRENT_SCANS,
    "--max-concurrent-scans exceeds the measured concurrency");
  const request = mebibytes(container.resources.requests.memory);
  const limit = mebibytes(container.resources.limits.memory);
  assert.ok(request >= MEASURED_PEAK_MIB, `memory request ${request} MiB is below the measured ${MEASURED_PEAK_MIB}`);
  const importCap = Number(argAfter(args, "--mesh-import-memory-mib"));
  assert.ok(limit >= MEASURED_PEAK_MIB + importCap,
    `memory limit ${limit} MiB cannot hold the scans and the mesh import process (${importCap} MiB) together`);
}

const [kubectl, kustomizeDir, containerfile] = process.argv.slice(2);
const uidMatch = /useradd[^\n]*--uid (\d+)[^\n]*vscan/.exec(readFileSync(containerfile, "utf8"));
assert.ok(uidMatch, `${containerfile} creates no vscan user with a fixed --uid`);
const containerUid = Number(uidMatch[1]);

const overlaysDir = join(kustomizeDir, "overlays");
const targets = ["base", ...readdirSync(overlaysDir).sort().map((o) => join("overlays", o))];
assert.ok(targets.length >= 2, "expected the base and at least one overlay");
const rendered = new Map();
for (const target of targets) {
  const dir = join(kustomizeDir, target);
  assert.ok(existsSync(join(dir, "kustomization.yaml")), `${dir} has no kustomization.yaml`);
  const objects = render(kubectl, dir);
  for (const object of objects) await validateAgainstSchema({ file: target, object });
  const set = only(objects, "StatefulSet");
  const namespace = only(objects, "Namespace");
  assert.equal(set.metadata.namespace, namespace.metadata.name, `${target}: the StatefulSet is outside its Namespace`);
  assert.equal(namespace.metadata.labels["pod-security.kubernetes.io/enforce"], "restricted");
  assert.ok(!/:latest$|^[^:]*$/.test(set.spec.template.spec.containers[0].image), `${target}: the image is not pinned`);
  checkService(only(objects, "Service"), set);
  checkServer(set, containerUid);
  rendered.set(target, set);
  console.log(`${target}: ${objects.map((o) => `${o.kind}/${o.metadata.name}`).join(", ")} valid,` +
    ` ${set.spec.replicas} replicas, namespace ${set.metadata.namespace ?? "(default)"}`);
}
assert.equal(rendered.get("overlays/dev")?.spec.replicas, 1, "the dev overlay runs a single replica");

const broken = structuredClone(rendered.get("base"));
broken.spec.template.spec.containers[0].readinessProbe.grpc.port = "grpc";
await expectRejected(broken, "a gRPC probe on a named port");

// Validates every manifest in a directory against the Kubernetes schema (kubernetes-models, offline)
// and checks that the dataset manifests fit together: the Indexed Job's shard count, the volume and
// ConfigMap they mount, the plan path (its bins described, meshes at absolute paths) and the dataset
// directory the shards and the merge share; both run vscand in one-shot mode; and that all of them
// live in a namespace that enforces the restricted Pod Security Standard, which the Jobs meet.
// Usage: node validate_manifests.mjs <manifest directory>

import assert from "node:assert/strict";
import { readdirSync, readFileSync } from "node:fs";
import { join } from "node:path";
import { parseAllDocuments, parse } from "yaml";
import { argAfter, expectRejected, validateAgainstSchema } from "./manifest_checks.mjs";

function loadManifests(dir) {
  const manifests = [];
  for (const file of readdirSync(dir).filter((f) => f.endsWith(".yaml")).sort()) {
    for (const doc of parseAllDocuments(readFileSync(join(dir, file), "utf8"))) {
      if (doc.errors.length > 0) throw new Error(`${file}: ${doc.errors[0].message}`);
      if (doc.contents !== null) manifests.push({ file, object: doc.toJS() });
    }
  }
  return manifests;
}

// Where a container sees the file or directory `path`: the volume mounted above it.
function volumeFor(pod, container, path) {
  const mount = container.volumeMounts.find((m) => path.startsWith(m.mountPath + "/"));
  assert.ok(mount, `${path} is under no volume mount of ${container.name}`);
  return { volume: pod.volumes.find((v) => v.name === mount.name), rest: path.slice(mount.mountPath.length + 1) };
}

function checkDataset(manifests) {
  const byKind = (kind) => manifests.map((m) => m.object).filter((o) => o.kind === kind);
  const claims = new Set(byKind("PersistentVolumeClaim").map((o) => o.metadata.name));
  const configMaps = new Map(byKind("ConfigMap").map((o) => [o.metadata.name, o]));
  const jobs = byKind("Job");
  const shards = jobs.filter((j) => j.spec.completionMode === "Indexed");
  assert.equal(shards.length, 1, "one Indexed Job writes the shards");
  const merges = jobs.filter((j) => j.spec.template.spec.containers[0].args.includes("--dataset-merge"));
  assert.equal(merges.length, 1, "one Job merges");

  const shardJob = shards[0];
  const shardArgs = shardJob.spec.template.spec.containers[0].args;
  assert.equal(argAfter(shardArgs, "--shard-index"), "$(JOB_COMPLETION_INDEX)");
  assert.equal(Number(argAfter(shardArgs, "--shard-count")), shardJob.spec.completions,
    "--shard-count must equal completions, or seeds are lost or written twice");
  assert.ok(shardJob.spec.parallelism >= 1 && shardJob.spec.parallelism <= shardJob.spec.completions);
  assert.equal(shardJob.spec.template.spec.restartPolicy, "Never");

  const outs = new Set();
  for (const [job, planFlag] of [[shardJob, "--dataset-shard"], [merges[0], "--dataset-merge"]]) {
    const pod = job.spec.template.spec;
    const container = pod.containers[0];
    assert.deepEqual(container.command, ["vscand"], `${job.metadata.name}: the pods run vscand in one-shot mode`);
    const planPath = argAfter(container.args, planFlag);
    const plan = volumeFor(pod, container, planPath);
    assert.ok(plan.volume.configMap, `${job.metadata.name}: --plan must come from a ConfigMap`);
    const configMap = configMaps.get(plan.volume.configMap.name);
    assert.ok(configMap, `${job.metadata.name}: ConfigMap ${plan.volume.configMap.name} is not among the manifests`);
    const planText = configMap.data[plan.rest];
    assert.ok(planText, `ConfigMap ${configMap.metadata.name} has no key ${plan.rest}`);
    const parsed = parse(planText);
    for (const key of ["bins", "seeds", "sensors"]) assert.ok(parsed[key], `the plan has no ${key}`);
    for (const bin of parsed.bins) {
      assert.ok(bin.bin && bin.parts, `bin ${bin.name ?? bin}: the pods fill bins, so each needs its bin and parts`);
      for (const part of bin.parts) {
        assert.ok(part.mesh?.startsWith("/"), `bin ${bin.name}: ${part.mesh} must be an absolute path in the image`);
      }
    }

    const out = argAfter(container.args, "--out");
    const data = volumeFor(pod, container, out);
    assert.ok(data.volume.persistentVolumeClaim, `${job.metadata.name}: --out must be on a PersistentVolumeClaim`);
    assert.ok(claims.has(data.volume.persistentVolumeClaim.claimName),
      `${job.metadata.name}: claim ${data.volume.persistentVolumeClaim.claimName} is not among the manifests`);
    outs.add(`${data.volume.persistentVolumeClaim.claimName}:${data.rest}`);
  }
  assert.equal(outs.size, 1, "the shards and the merge must write the same directory of the same claim");
  for (const claim of byKind("PersistentVolumeClaim")) {
    assert.ok(claim.spec.accessModes.includes("ReadWriteMany"), "pods on several nodes write the dataset at once");
  }
  return shardJob;
}

// Every object in the one declared namespace, which enforces the restricted Pod Security Standard,
// and every Job's pod set up as that standard demands, from a pinned image.
function checkRestricted(manifests) {
  const namespaces = manifests.map((m) => m.object).filter((o) => o.kind === "Namespace");
  assert.equal(namespaces.length, 1, "one Namespace holds the dataset objects");
  const namespace = namespaces[0];
  assert.equal(namespace.metadata.labels?.["pod-security.kubernetes.io/enforce"], "restricted");
  for (const { file, object } of manifests) {
    if (object.kind === "Namespace") continue;
    assert.equal(object.metadata.namespace, namespace.metadata.name, `${file}: ${object.kind} outside the namespace`);
    if (object.kind !== "Job") continue;
    const pod = object.spec.template.spec;
    assert.equal(pod.securityContext?.runAsNonRoot, true, `${file}: runAsNonRoot`);
    assert.ok(pod.securityContext.runAsUser > 0, `${file}: a non-root runAsUser`);
    assert.equal(pod.securityContext.fsGroup, pod.securityContext.runAsUser, `${file}: fsGroup makes the claim writable`);
    assert.equal(pod.securityContext.seccompProfile?.type, "RuntimeDefault", `${file}: seccomp`);
    for (const container of pod.containers) {
      const context = container.securityContext ?? {};
      assert.equal(context.allowPrivilegeEscalation, false, `${file}: ${container.name} may escalate privileges`);
      assert.deepEqual(context.capabilities?.drop, ["ALL"], `${file}: ${container.name} keeps capabilities`);
      assert.equal(context.readOnlyRootFilesystem, true, `${file}: ${container.name} root file system`);
      assert.ok(!/:latest$|^[^:]*$/.test(container.image), `${file}: ${container.image} is not pinned to a version`);
    }
  }
}

const dir = process.argv[2];
const manifests = loadManifests(dir);
assert.ok(manifests.length >= 5, `expected the namespace, volume, plan, shard and merge manifests in ${dir}`);
for (const manifest of manifests) await validateAgainstSchema(manifest);
const shardJob = checkDataset(manifests);
checkRestricted(manifests);

const broken = structuredClone(shardJob);
broken.spec.completionMode = "Sharded";
await expectRejected(broken, "completionMode Sharded");
const numericMount = structuredClone(shardJob);
numericMount.spec.template.spec.containers[0].volumeMounts[0].mountPath = 42;
await expectRejected(numericMount, "a numeric mountPath");

const names = manifests.map((m) => `${m.object.kind}/${m.object.metadata.name}`);
console.log(`${manifests.length} manifests valid: ${names.join(", ")}`);

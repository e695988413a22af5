// Checks shared by the manifest tests: the Kubernetes schema offline (npm package kubernetes-models)
// and container arguments.
import assert from "node:assert/strict";

// "batch/v1" -> kubernetes-models/batch/v1, "v1" -> kubernetes-models/v1.
export async function validateAgainstSchema({ file, object }) {
  const models = await import(`kubernetes-models/${object.apiVersion}`);
  const Model = models[object.kind];
  if (Model === undefined) throw new Error(`${file}: no kind ${object.kind} in ${object.apiVersion}`);
  new Model(object).validate();
}

// Proof that validation runs: an object the schema must refuse.
export async function expectRejected(object, what) {
  try {
    await validateAgainstSchema({ file: what, object });
  } catch {
    return;
  }
  throw new Error(`the schema accepted ${what}: validation is not running`);
}

// The value that follows `flag` in a container's args.
export function argAfter(args, flag) {
  const at = args.indexOf(flag);
  assert.ok(at >= 0 && at + 1 < args.length, `${flag} is missing from ${args.join(" ")}`);
  return args[at + 1];
}

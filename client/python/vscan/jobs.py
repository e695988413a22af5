"""Job calls of the Client: scan campaigns and model jobs as durable jobs (JobService)."""

import os

import grpc

from . import convert
from ._stubs import sensor_pb2  # noqa: F401  (puts the generated stubs on sys.path)
from .errors import from_rpc_error
from .models import _options, alignment_options, evaluation_options, reconstruction_options

from vscan.v1 import job_pb2, job_pb2_grpc  # noqa: E402

FINAL_STATES = (job_pb2.JOB_STATE_SUCCEEDED, job_pb2.JOB_STATE_FAILED, job_pb2.JOB_STATE_CANCELLED,
                job_pb2.JOB_STATE_INTERRUPTED)


def campaign_spec(scene_id, mount_id, viewpoints, rotations=1, rotation_step_deg=0.0, start_angle_deg=0.0,
                  width=640, height=480, hfov_deg=60.0, near=0.05, far=10.0, preset=None, noise=None, seed=0,
                  backend="raycast", fields=None, frame="world", encoder_noise=False, reject_collisions=False,
                  name="", align=False, reconstruct=False, evaluate=False, alignment=None, reconstruction=None,
                  evaluation=None, returned_light=None):
    """A CampaignSpec: viewpoints is a list of (position, target) pairs in world metres.

    align, reconstruct and evaluate run those parts on the scans as they come (the last two imply the
    first) and leave model.json; alignment, reconstruction and evaluation are their options, as a dict
    of the keyword arguments of alignment_options(), reconstruction_options() and
    evaluation_options(), or as the messages. returned_light lights every scan with the sensor's
    emitter and the objects' materials, as scan()'s does: True for every default, or a dict of
    ReturnedLight's fields."""
    spec = job_pb2.CampaignSpec(scene_id=scene_id, mount_id=mount_id, rotations=int(rotations),
                                rotation_step_deg=float(rotation_step_deg), start_angle_deg=float(start_angle_deg),
                                seed=int(seed), backend=convert.backend(backend), frame=convert.frame(frame),
                                apply_encoder_noise=bool(encoder_noise), reject_collisions=bool(reject_collisions),
                                name=name, align=bool(align), reconstruct=bool(reconstruct), evaluate=bool(evaluate))
    if alignment is not None:
        spec.alignment.CopyFrom(_options(alignment, alignment_options, "alignment"))
    if reconstruction is not None:
        spec.reconstruction.CopyFrom(_options(reconstruction, reconstruction_options, "reconstruction"))
    if evaluation is not None:
        spec.evaluation.CopyFrom(_options(evaluation, evaluation_options, "evaluation"))
    if preset:
        spec.sensor.preset = preset
    else:
        camera = spec.sensor.pinhole
        camera.width, camera.height = int(width), int(height)
        camera.near, camera.far = float(near), float(far)
        camera.horizontal_fov_deg = float(hfov_deg)
    for position, target in viewpoints:
        spec.viewpoints.add(position=convert.vector3(position, "position"), target=convert.vector3(target, "target"))
    if noise is not None:
        spec.noise.CopyFrom(noise)
    if fields:
        spec.fields.extend(convert.fields(fields))
    convert.returned_light(returned_light, spec.returned_light)
    return spec


class JobCalls:
    """Mixed into Client; uses its channel, metadata and call helpers."""

    @property
    def _jobs(self):
        stub = self.__dict__.get("_job_stub")
        if stub is None:
            stub = self.__dict__["_job_stub"] = job_pb2_grpc.JobServiceStub(self._channel)
        return stub

    def start_campaign(self, scene_id=None, mount_id=None, viewpoints=(), spec=None, **options):
        """Starts a scan campaign and returns its Job (QUEUED).

        Either a ready job_pb2.CampaignSpec as spec, or scene_id, mount_id, viewpoints
        [(position, target), ...] and the options of campaign_spec().
        """
        if spec is None:
            spec = campaign_spec(scene_id, mount_id, viewpoints, **options)
        return self._call(self._jobs.StartCampaign, job_pb2.StartCampaignRequest(spec=spec)).job

    def validate_campaign(self, scene_id="", mount_id="", viewpoints=(), spec=None, **options):
        """Checks a campaign as start_campaign would and starts nothing; raises VscanError naming the
        field. Empty scene_id and mount_id are not looked up (check a plan before building it)."""
        if spec is None:
            spec = campaign_spec(scene_id, mount_id, viewpoints, **options)
        self._call(self._jobs.StartCampaign, job_pb2.StartCampaignRequest(spec=spec, validate_only=True))

    def get_job(self, job_id):
        return self._call(self._jobs.GetJob, job_pb2.GetJobRequest(job_id=job_id)).job

    def list_jobs(self):
        return self._pages(self._jobs.ListJobs, job_pb2.ListJobsRequest, "jobs")

    def cancel_job(self, job_id):
        """Asks the job to stop; a running one ends CANCELLED after its current scan."""
        return self._call(self._jobs.CancelJob, job_pb2.CancelJobRequest(job_id=job_id)).job

    def resume_job(self, job_id):
        """Runs an ended campaign (INTERRUPTED, CANCELLED or FAILED) again as the same job: the scans
        it stored are kept, only the missing steps are captured, campaign.json is written anew.
        Returns the job as queued again; follow it with wait_job or watch_job.

        Raises VscanError with NOT_FOUND for an unknown id, FAILED_PRECONDITION for a job that
        succeeded, has not ended or is not a campaign, RESOURCE_EXHAUSTED when the queue is full."""
        return self._call(self._jobs.ResumeJob, job_pb2.ResumeJobRequest(job_id=job_id)).job

    def delete_job(self, job_id):
        """Deletes an ended job and its artifacts; returns DeleteJobResponse (files and bytes freed).

        Raises VscanError with FAILED_PRECONDITION while the job is queued or running (cancel it
        first), NOT_FOUND for an unknown id."""
        return self._call(self._jobs.DeleteJob, job_pb2.DeleteJobRequest(job_id=job_id))

    def watch_job(self, job_id, timeout=None):
        """Yields WatchJobResponse messages: the job as it is, then one per event until it ends."""
        stream = self._jobs.WatchJob(job_pb2.WatchJobRequest(job_id=job_id), timeout=timeout or self._stream_timeout,
                                     metadata=self._metadata)
        try:
            yield from stream
        except grpc.RpcError as err:
            raise from_rpc_error(err) from None
        finally:
            stream.cancel()

    def wait_job(self, job_id, timeout=None):
        """Follows the job until it ends and returns it as GetJob does (with every artifact)."""
        for _ in self.watch_job(job_id, timeout=timeout):
            pass
        return self.get_job(job_id)

    def read_artifact(self, job_id, artifact_id):
        """Returns (Artifact, bytes) of one file a job produced."""
        stream = self._jobs.ReadArtifact(job_pb2.ReadArtifactRequest(job_id=job_id, artifact_id=artifact_id),
                                         timeout=self._stream_timeout, metadata=self._metadata)
        artifact, chunks = None, []
        try:
            for message in stream:
                if artifact is None:
                    artifact = message.artifact
                chunks.append(message.chunk)
        except grpc.RpcError as err:
            raise from_rpc_error(err) from None
        return artifact, b"".join(chunks)

    def download_artifacts(self, job_id, directory, names=None):
        """Writes the job's artifacts (only those named in names, when given) into directory, created
        if needed; returns the paths written."""
        os.makedirs(directory, exist_ok=True)
        paths = []
        for artifact in self.get_job(job_id).artifacts:
            if names is not None and artifact.name not in names:
                continue
            _, data = self.read_artifact(job_id, artifact.artifact_id)
            # An artifact's name is a plain file name; anything else is written under its id.
            name = artifact.name
            if not name or name in (".", "..") or "/" in name or "\\" in name:
                name = artifact.artifact_id
            path = os.path.join(directory, name)
            with open(path, "wb") as f:
                f.write(data)
            paths.append(path)
        return paths

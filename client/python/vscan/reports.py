"""The JSON reports jobs leave (model.json, campaign.json, bin.json, picking.json and its steps'
step-NNN-truth.json), read through their messages in proto/vscan/v1/reports.proto: the keys are the
schema's, so a report and its readers cannot drift."""

import grpc
from google.protobuf import json_format

from ._stubs import sensor_pb2  # noqa: F401  (puts the generated stubs on sys.path)
from .errors import VscanError

from vscan.v1 import reports_pb2  # noqa: E402

REPORT_MESSAGES = {"model.json": reports_pb2.ModelReport, "campaign.json": reports_pb2.CampaignReport,
                   "bin.json": reports_pb2.BinReport, "picking.json": reports_pb2.PickingReport}


def _message_for(name):
    """The report message of a file name; a picking step's step-NNN-truth.json is a PickingStepTruth."""
    if name.startswith("step-") and name.endswith("-truth.json"):
        return reports_pb2.PickingStepTruth
    return REPORT_MESSAGES[name]


def parse_report(name, data):
    """The report called name (bytes or text) as a dict with the file's keys: every field the schema
    always prints is there (at its default when the file left it out); keys the schema does not
    know are passed over. Raises VscanError DATA_LOSS for what the schema cannot read."""
    try:
        message = json_format.Parse(data, _message_for(name)(), ignore_unknown_fields=True)
    except json_format.ParseError as err:
        raise VscanError(grpc.StatusCode.DATA_LOSS, f"{name}: {err}") from None
    return report_dict(message)


def report_dict(message):
    """A report message as the dict its JSON file reads as."""
    try:
        return json_format.MessageToDict(message, preserving_proto_field_name=True,
                                         always_print_fields_with_no_presence=True)
    except TypeError:  # protobuf before 26 calls it including_default_value_fields
        return json_format.MessageToDict(message, preserving_proto_field_name=True,
                                         including_default_value_fields=True)

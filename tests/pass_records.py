"""The passes a method call runs, recorded as it runs them, for tests that rerun one of a
method's passes on its own (with a define changed, against its separate twin) without naming
the method's module: what PassRunner.run was given, with the defines and uniforms it resolved."""

from __future__ import annotations

from contextlib import contextmanager
from dataclasses import dataclass
from unittest import mock

from blurlab.methods import plans
from blurlab.methods.core import choice_defines, pass_uniforms
from blurlab.methods.passes import PassRunner


@dataclass(frozen=True)
class RecordedPass:
    """One pass of a method call: its declaration, its #defines and its uniforms."""

    step: object  # the Pass: name, shader, params
    defines: dict
    uniforms: dict


@contextmanager
def recorded_passes():
    """Within it, every pass a method runs through PassRunner.run is appended, in order, to the
    list it yields (plans are off, so that a replay does not skip the record)."""
    runs: list[RecordedPass] = []
    original = PassRunner.run

    def run(self, step, inputs, outputs, backend="compute", uniforms=None, defines=None, **rest):
        all_defines = {**choice_defines(self.params, step.params), **(defines or {})}
        all_uniforms = {**pass_uniforms(self.params, self.values, step.params), **(uniforms or {})}
        runs.append(RecordedPass(step, all_defines, all_uniforms))
        return original(self, step, inputs, outputs, backend, uniforms, defines, **rest)

    with mock.patch.object(PassRunner, "run", run), plans.disabled():
        yield runs


def the_pass(runs: list[RecordedPass], name: str) -> RecordedPass:
    """The one recorded pass timed as `name`."""
    (found,) = [r for r in runs if r.step.name == name]
    return found

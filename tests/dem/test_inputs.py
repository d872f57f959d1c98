"""The inputs of a DEM run live in ``pdamper.dem.inputs``; the former module name
``pdamper.dem.model`` stays importable and is the same module."""

import pickle
import subprocess
import sys

from pdamper.dem import Container, inputs
from pdamper.materials import get_material
from proc import env


def test_the_former_module_name_is_the_same_module():
    from pdamper.dem import model
    from pdamper.dem.model import LargeOverlapWarning, ParticleSet

    assert model is inputs
    assert LargeOverlapWarning is inputs.LargeOverlapWarning
    assert ParticleSet is inputs.ParticleSet
    assert Container.__module__ == "pdamper.dem.inputs"


def test_a_warning_filter_by_the_former_name_resolves_in_a_fresh_process():
    code = ("import warnings\n"
            "warnings.filterwarnings('error', category=__import__("
            "'pdamper.dem.model', fromlist=['x']).LargeOverlapWarning)\n"
            "from pdamper.dem.inputs import LargeOverlapWarning\n"
            "try:\n    warnings.warn('x', LargeOverlapWarning)\n"
            "except LargeOverlapWarning:\n    print('caught')\n")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True, env=env())
    assert out.stdout.strip() == "caught"


def test_inputs_pickle_under_their_module():
    box = Container((0.06, 0.06, 0.12), get_material("S235"))
    assert pickle.loads(pickle.dumps(box)) == box

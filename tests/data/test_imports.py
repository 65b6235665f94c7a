"""Reading and writing acquisitions must not load the simulator (e.g. `ftfof import-logs`)."""

import subprocess
import sys


def test_the_data_package_and_the_sample_record_import_no_exudyn():
    code = (
        "import sys, ftfof.data, ftfof.data.logs, ftfof.data.acquisition, ftfof.sim.records; "
        "assert 'exudyn' not in sys.modules, 'exudyn was imported'"
    )
    subprocess.run([sys.executable, "-c", code], check=True)

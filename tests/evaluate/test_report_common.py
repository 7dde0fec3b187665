"""The report header says which trial-to-trial variability sources were simulated."""

from vibrissa.evaluate.report_common import report_header


def _meta(**dataset):
    return {
        "title": "T",
        "vibrissa_version": "0",
        "command": "c",
        "dataset": {"path": "/x/d.nc", "n_trials": 4, **dataset},
    }


def test_the_header_names_the_variability_sources_that_were_on():
    text = report_header(_meta(variability_sources=["hall_drift", "placement"]))
    assert "trial-to-trial variability simulated" in text and "hall_drift, placement" in text
    assert "variability simulated (`robots.xy_variability`): none" in report_header(
        _meta(variability_sources=[])
    )


def test_a_run_without_the_key_says_nothing_about_variability():
    assert "variability" not in report_header(_meta())

"""The local cluster's Dask settings reach the worker processes, where the periodic work runs."""

from __future__ import annotations

import dask

from robogen.campaign.engine import LOCAL_CLUSTER_CONFIG, connect


def _settings(keys):
    return [dask.config.get(key) for key in keys]


def test_the_local_clusters_workers_run_with_its_settings():
    keys = ["distributed.worker.profile.enabled", "distributed.admin.tick.interval",
            "distributed.worker.memory.monitor-interval", "distributed.admin.system-monitor.interval"]
    lines = []
    with connect(2, None, lines.append) as client:
        seen = client.run(_settings, keys)
    assert len(seen) == 2 and lines[0].startswith("Dask: a local cluster (2 worker processes, 1 thread each)")
    for values in seen.values():
        assert values == [False, "1s", "1s", "2s"] == [LOCAL_CLUSTER_CONFIG[k] for k in keys]
    assert _settings(keys)[0] is not False  # the client's own configuration is left as it was

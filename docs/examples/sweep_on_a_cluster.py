"""A sweep of four designs on a dask cluster: here a LocalCluster of two worker processes."""

import dask
from distributed import Client, LocalCluster

import windpump

designs = [windpump.Design.seed_example().replace(h=h) for h in (1.0, 2.0, 3.0, 4.0)]
# dask starts workers with MALLOC_TRIM_THRESHOLD_=65536, which makes every run's sample arrays
# fresh pages: runs cost ~3x more. Unset it before the workers start (or in the cluster's config).
dask.config.set({"distributed.nanny.pre-spawn-environ.MALLOC_TRIM_THRESHOLD_": None})

if __name__ == "__main__":  # workers are new processes: a script needs the guard
    with LocalCluster(n_workers=2, threads_per_worker=1, dashboard_address=None) as cluster:
        with Client(cluster) as client:
            table = windpump.sweep(designs, 600.0, executor=client.get_executor())
    assert list(table.stalled) == [False] * 4

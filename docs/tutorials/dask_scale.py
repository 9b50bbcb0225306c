"""A study at scale: a Parquet dataset written chunk by chunk on a local Dask cluster."""

import tempfile

import pandas as pd

import polyell as pe

if __name__ == "__main__":  # Dask starts worker processes: guard the entry point
    panda = pe.robots.load("panda")
    low, high = panda.position_limits
    configurations = pe.random_configurations(20_000, low, high, seed=1)  # lazy
    with tempfile.TemporaryDirectory() as folder:
        out = pe.sweep(panda, configurations, out=folder, chunk=5_000, scheduler="processes")
        dataset = pd.read_parquet(out)
        print(len(dataset), "rows in", len(list(out.glob("part-*.parquet"))), "Parquet parts")
        print(
            "median coverage:",
            dataset[["chiacchio_coverage", "yoshikawa_coverage"]].median().round(4).to_dict(),
        )
        # Started again with the same arguments, a sweep computes only missing chunks:
        pe.sweep(panda, configurations, out=folder, chunk=5_000)
        print("resumed: still", len(pd.read_parquet(out)), "rows")

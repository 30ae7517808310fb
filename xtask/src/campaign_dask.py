"""Runs `harness monte-carlo` shards as Dask tasks (run by `cargo xtask campaign-dask`).

Each task is one shard's command line; a worker runs it as a subprocess and returns its exit
code and output. Without --scheduler a LocalCluster of --workers single-threaded worker
processes is started on this machine (loopback); with it, the tasks go to that cluster, whose
workers must see the harness binary, the FMU directory and the output directory at the same
paths (a shared file system).
"""
import argparse
import subprocess
import sys


def fly_shard(command):
    done = subprocess.run(command, capture_output=True, text=True)
    return done.returncode, done.stdout, done.stderr


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--workers", type=int, required=True)
    parser.add_argument("--scheduler")
    parser.add_argument(
        "--commands", required=True, help="one shard command per line, arguments tab-separated"
    )
    args = parser.parse_args()
    with open(args.commands) as f:
        commands = [line.rstrip("\n").split("\t") for line in f if line.strip()]

    from dask.distributed import Client, LocalCluster

    if args.scheduler:
        client = Client(args.scheduler)
        cluster = None
    else:
        cluster = LocalCluster(
            n_workers=args.workers,
            threads_per_worker=1,
            processes=True,
            host="127.0.0.1",
            dashboard_address=None,
        )
        client = Client(cluster)
    try:
        print(f"campaign-dask: {len(commands)} shards on {client}", flush=True)
        futures = client.map(fly_shard, commands, pure=False)
        failed = 0
        for k, (code, out, err) in enumerate(client.gather(futures), start=1):
            # 3: the shard flew, some flights failed their verdict (reported after the merge).
            if code not in (0, 3):
                failed += 1
                print(f"shard {k}: exit {code}\n{out}{err}", file=sys.stderr)
            else:
                last = out.strip().splitlines()[:1]
                print(f"shard {k}: {last[0] if last else 'done'}", flush=True)
    finally:
        client.close()
        if cluster is not None:
            cluster.close()
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())

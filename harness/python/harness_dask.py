"""Flies the shards of a harness campaign as Dask tasks on workers that share no file system
with this machine. `harness monte-carlo ... --dask ADDRESS` (or `harness campaign ...`) writes
a job file (JSON) and runs this script on it with `python3` (or $HARNESS_PYTHON); docs/dask.md says how to use it.

Each task carries what it needs: the harness binary for its worker's platform, the FMUs, the
scenario file and the file declaring its campaign (their bytes), and the subcommand's arguments. On its worker it writes them
into a temporary directory of its own (under the worker's --local-directory), runs

    harness --fmu-dir fmu SUBCOMMAND ARGS --shard k/S --out-dir out --quiet --no-plots --workers 1

there, returns the bytes of the shard's files and deletes the directory. This script writes
each returned shard into the job's store, `<store>/shard-<k>-of-<S>/`, with the address of
the worker that flew it in `dask.txt`; the harness then merges the shards. A shard whose
worker is lost is run again by the scheduler; with `--resume` the shards already in the
store are not flown again.

The job file: {"scheduler": "tcp://HOST:PORT" or "local:N", "subcommand": "monte-carlo",
"args": [...], "files": {"fmu/X.fmu": "/path", "scenario/s.toml": "/path"},
"harnesses": {"x86_64-linux": "/path/harness", ...}, "store": "/path", "flights": F,
"unit": "flights" or "runs" (what the progress lines call them), "shards": S or null,
"done": [k, ...], "quiet": false}.
"""
import json
import os
import sys
import time
import uuid

# Printed before the message that stops the run, so that the harness finds it in stderr.
PREFIX = "harness-dask: "
# Shards per worker when the job names no count: enough to even out slow and fast shards.
SHARDS_PER_WORKER = 4


def fail(message):
    print(PREFIX + message, file=sys.stderr, flush=True)
    return 1


def platform_tag():
    """This machine as the release's `bin/` folders name platforms: x86_64-linux, ..."""
    import platform

    system = platform.system().lower()
    system = {"darwin": "macos"}.get(system, system)
    machine = platform.machine().lower()
    machine = {"amd64": "x86_64", "x64": "x86_64", "arm64": "aarch64"}.get(machine, machine)
    return f"{machine}-{system}"


def value(x):
    """A task whose result is its argument: the shipped bytes, held by the scheduler in the
    task's definition, so that a worker lost with them makes the scheduler run it again."""
    return x


def flights_of(k, shards, flights):
    """How many flights shard k of `shards` flies: those whose index is k-1 modulo shards."""
    return len(range(k - 1, flights, shards))


def fly_shard(k, shards, subcommand, args, files, harnesses):
    """On a worker: flies shard k of `shards` in a temporary directory of its own and returns
    the shard's files, the worker's address, where it ran and how long it took."""
    import shutil
    import subprocess
    import tempfile

    tag = platform_tag()
    if tag not in harnesses:
        raise RuntimeError(
            f"no harness for this worker's platform {tag}: the job ships "
            f"{', '.join(sorted(harnesses))}"
        )
    try:
        from distributed import get_worker

        worker = get_worker()
        address, local = worker.address, worker.local_directory
    except (ImportError, ValueError):
        address, local = "?", None
    started = time.monotonic()
    tmp = tempfile.mkdtemp(prefix="harness-dask-", dir=local)
    try:
        exe = os.path.join(tmp, "harness.exe" if tag.endswith("-windows") else "harness")
        with open(exe, "wb") as f:
            f.write(harnesses[tag])
        os.chmod(exe, 0o755)
        for relative, data in files.items():
            path = os.path.join(tmp, *relative.split("/"))
            os.makedirs(os.path.dirname(path), exist_ok=True)
            with open(path, "wb") as f:
                f.write(data)
        os.makedirs(os.path.join(tmp, "fmu"), exist_ok=True)
        argv = [exe, "--fmu-dir", os.path.join(tmp, "fmu"), subcommand, *args]
        argv += ["--shard", f"{k}/{shards}", "--out-dir", "out"]
        argv += ["--quiet", "--no-plots", "--workers", "1"]
        env = dict(os.environ)
        env.pop("LANDER_FMU_DIR", None)
        done = subprocess.run(argv, cwd=tmp, capture_output=True, env=env)
        out = os.path.join(tmp, "out")
        # The summary is written once every flight of the shard has its row; a shard whose
        # flights ended in error (exit code 1) or failed their verdict (3) has one too.
        if not os.path.isfile(os.path.join(out, "summary.csv")):
            stderr = done.stderr.decode(errors="replace").strip()
            raise RuntimeError(
                f"shard {k}/{shards}: the harness ended with exit code {done.returncode} on "
                f"worker {address} ({tag}):\n{stderr[-4000:]}"
            )
        shard_files = {}
        for name in sorted(os.listdir(out)):
            path = os.path.join(out, name)
            if os.path.isfile(path):
                with open(path, "rb") as f:
                    shard_files[name] = f.read()
        return {
            "k": k,
            "worker": address,
            "dir": tmp,
            "seconds": time.monotonic() - started,
            "files": shard_files,
        }
    finally:
        shutil.rmtree(tmp, ignore_errors=True)


def write_shard(store, shards, result):
    """The shard's files into <store>/shard-<k>-of-<S>/, complete or not at all."""
    import shutil

    final = os.path.join(store, f"shard-{result['k']}-of-{shards}")
    partial = final + ".partial"
    shutil.rmtree(partial, ignore_errors=True)
    os.makedirs(partial)
    for name, data in result["files"].items():
        with open(os.path.join(partial, name), "wb") as f:
            f.write(data)
    with open(os.path.join(partial, "dask.txt"), "w") as f:
        f.write(result["worker"] + "\n")
    shutil.rmtree(final, ignore_errors=True)
    os.replace(partial, final)


def connect(address):
    """A client of the scheduler at `address`, or of a LocalCluster of N single-threaded
    worker processes on loopback for `local:N`; and the cluster to close after."""
    from distributed import Client, LocalCluster

    if address.startswith("local:"):
        count = address[len("local:") :]
        if not count.isdigit() or int(count) < 1:
            raise ValueError(f"--dask {address}: local:N wants a number of workers N >= 1")
        cluster = LocalCluster(
            n_workers=int(count),
            threads_per_worker=1,
            processes=True,
            host="127.0.0.1",
            dashboard_address=None,
        )
        return Client(cluster), cluster
    return Client(address, timeout="30s"), None


def run(job, client):
    from distributed import as_completed

    flights = job["flights"]
    unit = job.get("unit", "flights")
    client.wait_for_workers(1, timeout=120)
    platforms = client.run(platform_tag)
    shipped = job["harnesses"]
    lacking = sorted({tag for tag in platforms.values() if tag not in shipped})
    if lacking:
        workers = [w for w, tag in platforms.items() if tag in lacking]
        return fail(
            f"workers of platform {', '.join(lacking)} ({', '.join(workers)}) have no harness: "
            f"this harness ships {', '.join(sorted(shipped))} (a release's bin/<platform>/); "
            f"run those workers elsewhere, or from a container image with the release"
        )
    shards = job["shards"] or max(1, min(flights, SHARDS_PER_WORKER * len(platforms)))
    done = set(job["done"])
    todo = [k for k in range(1, shards + 1) if k not in done]
    flown = sum(flights_of(k, shards, flights) for k in done)

    files = {}
    for relative, path in job["files"].items():
        with open(path, "rb") as f:
            files[relative] = f.read()
    harnesses = {}
    for tag in sorted(set(platforms.values())):
        with open(shipped[tag], "rb") as f:
            harnesses[tag] = f.read()
    files_bytes = sum(map(len, files.values()))
    harness_bytes = sum(map(len, harnesses.values()))
    quiet = job["quiet"]
    if not quiet:
        print(
            f"dask: {shards} shards of {flights} {unit} on {job['scheduler']}, "
            f"{len(platforms)} workers ({', '.join(sorted(set(platforms.values())))}); "
            f"shards done before: {len(done)}; each worker receives once "
            f"{(files_bytes + harness_bytes) / 1e6:.1f} MB (harness {harness_bytes / 1e6:.1f} MB, "
            f"FMUs and scenario {files_bytes / 1e6:.1f} MB)",
            flush=True,
        )
    if not todo:
        return 0
    run_id = uuid.uuid4().hex[:8]
    files_future = client.submit(value, files, key=f"harness-files-{run_id}")
    harness_future = client.submit(value, harnesses, key=f"harness-binaries-{run_id}")
    futures = [
        client.submit(
            fly_shard,
            k,
            shards,
            job["subcommand"],
            job["args"],
            files_future,
            harness_future,
            key=f"harness-shard-{k}-of-{shards}-{run_id}",
        )
        for k in todo
    ]
    for future in as_completed(futures):
        try:
            result = future.result()
        except Exception as error:  # the task's own error, or KilledWorker
            client.cancel(futures)
            return fail(f"{type(error).__name__}: {error}")
        write_shard(job["store"], shards, result)
        # Stored: the cluster may forget it (a lost worker's copy is not computed again).
        future.release()
        k = result["k"]
        flown += flights_of(k, shards, flights)
        shipped_back = sum(map(len, result["files"].values()))
        if not quiet:
            print(
                f"dask: shard {k}/{shards} flown by {result['worker']} in {result['dir']} "
                f"({result['seconds']:.1f} s, {shipped_back} bytes back): "
                f"{flown}/{flights} {unit}",
                flush=True,
            )
    return 0


def main():
    if len(sys.argv) != 2:
        return fail("usage: harness_dask.py JOB.json (written by `harness ... --dask`)")
    with open(sys.argv[1]) as f:
        job = json.load(f)
    for module in ("dask", "distributed"):
        try:
            __import__(module)
        except ImportError:
            return fail(
                f"{sys.executable} has no Python module '{module}', which --dask needs: "
                f"install it with `{sys.executable} -m pip install dask distributed` "
                f"(or name another Python in HARNESS_PYTHON)"
            )
    try:
        client, cluster = connect(job["scheduler"])
    except Exception as error:
        return fail(f"cannot reach the Dask scheduler at {job['scheduler']}: {error}")
    try:
        return run(job, client)
    except Exception as error:  # no worker in time, a lost connection: said in one line
        return fail(f"{type(error).__name__}: {error}")
    finally:
        client.close()
        if cluster is not None:
            cluster.close()


if __name__ == "__main__":
    sys.exit(main())

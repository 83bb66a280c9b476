"""Batch meshing on Dask: ``python3 -m mesohex.batch MANIFEST [--scheduler ADDRESS]``.

MANIFEST is a CSV file with the header ``skeleton,surface,output`` and an optional ``options`` column holding CLI
flags (``--levels 1 --partitions 4``). A row with a skeleton runs ``mesohex mesh SKELETON --surface SURFACE -o
OUTPUT``; an empty skeleton runs ``mesohex auto SURFACE -o OUTPUT``. Relative paths are relative to the manifest.

Every job runs the ``mesohex`` executable in its own process on a Dask worker, with a timeout: a crash or a timeout
fails that job only (its stderr is kept in the results), and is retried (``--retries``), as is a job whose worker
died; bad input (exit status 2, 3 or 4) is not retried, since it would fail again. The results table (``--results PREFIX``: PREFIX.csv and PREFIX.json;
default: the manifest's name + ``.results``) is rewritten atomically as each job finishes, with for every job: status,
exit code, hexes, min/avg scaled Jacobian, inverted hexes, Hausdorff distance, seconds, attempts, the JSON report's
path and the end of stderr. A rerun skips the jobs the table records as done (status ``ok`` or ``inverted``, output
file present), so an interrupted batch resumes where it stopped.

Without ``--scheduler`` a local cluster runs on this machine (``--workers`` processes, default 2, bound to
127.0.0.1). With ``--scheduler tcp://HOST:8786`` the jobs go to a running Dask cluster (see docs/batch.md); its
workers need the ``mesohex`` executable (``--mesohex``) and the files at the same paths (a shared file system).

Exit status: 0 when every job is done, 1 when some job failed, 2 for an unusable manifest or arguments.
"""
import argparse
import csv
import json
import os
import shlex
import socket
import subprocess
import sys
import tempfile
import time

# Exit statuses of the `mesohex` CLI (see apps/cli/main.cpp).
EXIT_OK = 0
EXIT_INVERTED = 5  # the mesh was written but has inverted hexes
EXIT_NOT_RETRIED = (2, 3, 4)  # invalid input, unsupported configuration, file error: the same again on a retry

DONE_STATUSES = ("ok", "inverted")
RESULT_COLUMNS = ["row", "skeleton", "surface", "output", "options", "command", "status", "exit_code", "hexes",
                  "sj_min", "sj_avg", "inverted", "hausdorff", "hausdorff_relative", "seconds", "attempts", "worker",
                  "report", "stderr"]
STDERR_KEPT_CHARS = 20000  # in the JSON table (the CSV keeps the last 500)


def default_cli():
    """The `mesohex` executable: $MESOHEX_CLI, else the one of the build this package belongs to, else on PATH."""
    if os.environ.get("MESOHEX_CLI"):
        return os.environ["MESOHEX_CLI"]
    try:
        from ._build_paths import MESOHEX_CLI
        if os.path.exists(MESOHEX_CLI):
            return MESOHEX_CLI
    except ImportError:
        pass
    return "mesohex"


class ManifestError(Exception):
    pass


def read_manifest(path):
    """The jobs of a manifest: dicts with row (1-based data row), skeleton, surface, output, options, command."""
    base = os.path.dirname(os.path.abspath(path))

    def resolve(p):
        return os.path.normpath(os.path.join(base, p)) if p else ""

    try:
        with open(path, newline="") as f:
            reader = csv.DictReader(f)
            header = [h.strip() for h in (reader.fieldnames or [])]
            missing = [c for c in ("skeleton", "surface", "output") if c not in header]
            if missing:
                raise ManifestError("%s:1: the header must name skeleton,surface,output (missing: %s)"
                                    % (path, ", ".join(missing)))
            reader.fieldnames = header
            jobs = []
            for row in reader:
                line = reader.line_num
                values = {k: (v or "").strip() for k, v in row.items() if k is not None}
                if not any(values.values()):
                    continue  # blank line
                if not values.get("output"):
                    raise ManifestError("%s:%d: no output" % (path, line))
                if not values.get("skeleton") and not values.get("surface"):
                    raise ManifestError("%s:%d: neither a skeleton nor a surface" % (path, line))
                try:
                    options = shlex.split(values.get("options", ""))
                except ValueError as e:
                    raise ManifestError("%s:%d: options: %s" % (path, line, e))
                job = {"row": len(jobs) + 1, "line": line, "skeleton": resolve(values.get("skeleton")),
                       "surface": resolve(values.get("surface")), "output": resolve(values["output"]),
                       "options": values.get("options", "")}
                job["report"] = job["output"] + ".report.json"
                if job["skeleton"]:
                    args = ["mesh", job["skeleton"]] + (["--surface", job["surface"]] if job["surface"] else [])
                else:
                    args = ["auto", job["surface"]]
                job["args"] = args + ["-o", job["output"], "--report", job["report"], "--quiet"] + options
                jobs.append(job)
    except OSError as e:
        raise ManifestError("%s: cannot read the manifest: %s" % (path, e.strerror))
    except csv.Error as e:
        raise ManifestError("%s: not a CSV file: %s" % (path, e))
    outputs = {}
    for job in jobs:
        if job["output"] in outputs:
            raise ManifestError("%s:%d: output %s is also the output of line %d"
                                % (path, job["line"], job["output"], outputs[job["output"]]))
        outputs[job["output"]] = job["line"]
    return jobs


def run_job(job, cli, timeout, threads):
    """Runs one job in its own process (on a worker) and returns its result record; record["retryable"] says whether
    a retry may help (crash, timeout, unexpected exit status)."""
    args = [cli] + job["args"]
    if threads > 0 and "--threads" not in job["args"]:
        args += ["--threads", str(threads)]
    record = {k: job[k] for k in ("row", "skeleton", "surface", "output", "options", "report")}
    record.update(command=" ".join(shlex.quote(a) for a in args), worker=socket.gethostname(), retryable=False)
    start = time.monotonic()
    try:
        proc = subprocess.run(args, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, timeout=timeout)
        stderr = proc.stderr.decode(errors="replace")
        code = proc.returncode
    except subprocess.TimeoutExpired as e:
        stderr = (e.stderr or b"").decode(errors="replace") + "\nmesohex.batch: killed after %g s (timeout)" % timeout
        record.update(status="timeout", exit_code=None, seconds=time.monotonic() - start, stderr=stderr,
                      retryable=True)
        return record
    except OSError as e:
        record.update(status="failed", exit_code=None, seconds=time.monotonic() - start,
                      stderr="mesohex.batch: cannot run %s: %s" % (cli, e))
        return record
    record.update(exit_code=code, seconds=time.monotonic() - start, stderr=stderr[-STDERR_KEPT_CHARS:])
    if code in (EXIT_OK, EXIT_INVERTED):
        record["status"] = "ok" if code == EXIT_OK else "inverted"
        record.update(read_report(job["report"]))
        return record
    if code in EXIT_NOT_RETRIED:
        record["status"] = "failed"
        return record
    record["status"] = "crashed" if code < 0 else "failed"
    if code < 0:
        record["stderr"] += "\nmesohex.batch: killed by signal %d" % -code
    record["retryable"] = True
    return record


def read_report(path):
    """hexes, sj_min, sj_avg, inverted, hausdorff from a `--report` JSON file (empty when it cannot be read)."""
    try:
        with open(path) as f:
            rep = json.load(f)
    except (OSError, ValueError):
        return {}
    q = rep.get("quality", {})
    out = {"hexes": q.get("hexes"), "sj_min": q.get("sj_min"), "sj_avg": q.get("sj_avg"),
           "inverted": q.get("inverted")}
    h = rep.get("hausdorff")
    if isinstance(h, dict):
        out.update(hausdorff=h.get("max"), hausdorff_relative=h.get("relative_max"))
    return out


def write_atomically(path, text):
    fd, tmp = tempfile.mkstemp(prefix=os.path.basename(path) + ".tmp.", dir=os.path.dirname(os.path.abspath(path)))
    try:
        with os.fdopen(fd, "w", newline="") as f:
            f.write(text)
        os.replace(tmp, path)
    except BaseException:
        if os.path.exists(tmp):
            os.unlink(tmp)
        raise


def write_results(prefix, records):
    """PREFIX.json (a list of records, in manifest order) and PREFIX.csv (the same, stderr cut to its end)."""
    ordered = [records[k] for k in sorted(records, key=lambda k: records[k].get("row", 0))]
    write_atomically(prefix + ".json", json.dumps(ordered, indent=1) + "\n")
    import io
    buf = io.StringIO()
    w = csv.DictWriter(buf, fieldnames=RESULT_COLUMNS, extrasaction="ignore")
    w.writeheader()
    for r in ordered:
        row = {k: ("" if r.get(k) is None else r.get(k)) for k in RESULT_COLUMNS}
        row["stderr"] = (r.get("stderr") or "")[-500:]
        if isinstance(row["seconds"], float):
            row["seconds"] = "%.3f" % row["seconds"]
        w.writerow(row)
    write_atomically(prefix + ".csv", buf.getvalue())


def load_results(prefix):
    """Records of an earlier run, by output path ({} when there is none)."""
    try:
        with open(prefix + ".json") as f:
            return {r["output"]: r for r in json.load(f) if isinstance(r, dict) and "output" in r}
    except (OSError, ValueError):
        return {}


def is_done(record):
    return record is not None and record.get("status") in DONE_STATUSES and os.path.exists(record["output"])


def run_batch(jobs, client, prefix, cli, timeout, retries, threads, log=print):
    """Submits every job not done yet, writes the table as they finish. Returns the result records by output."""
    from dask.distributed import as_completed

    records = load_results(prefix)
    known = {job["output"] for job in jobs}
    records = {k: v for k, v in records.items() if k in known}
    todo = []
    for job in jobs:
        if is_done(records.get(job["output"])):
            records[job["output"]]["row"] = job["row"]
            log("batch: row %d done before, skipped: %s" % (job["row"], job["output"]))
        else:
            todo.append(job)
    attempts = {}  # output -> attempt number of its current submission
    futures = {}  # future key -> job

    def submit(job, attempt):
        attempts[job["output"]] = attempt
        fut = client.submit(run_job, job, cli, timeout, threads, pure=False,
                            key="mesohex-row%d-attempt%d-%s" % (job["row"], attempt, os.urandom(4).hex()))
        futures[fut.key] = job
        return fut

    pending = as_completed([submit(job, 1) for job in todo])
    for fut in pending:
        job = futures.pop(fut.key)
        n = attempts[job["output"]]
        try:
            record = fut.result()
            if record.pop("retryable") and n <= retries:
                log("batch: row %d %s (attempt %d), retrying: %s" % (job["row"], record["status"], n, job["output"]))
                pending.add(submit(job, n + 1))
                continue
        except Exception as e:  # the worker died, or Dask failed otherwise
            record = {k: job[k] for k in ("row", "skeleton", "surface", "output", "options", "report")}
            record.update(status="crashed", exit_code=None, stderr="mesohex.batch: %s: %s" % (type(e).__name__, e))
            if n <= retries:
                log("batch: row %d lost (%s), retrying" % (job["row"], type(e).__name__))
                pending.add(submit(job, n + 1))
                continue
        record["attempts"] = n
        records[job["output"]] = record
        write_results(prefix, records)
        log("batch: row %d %s in %.1f s%s: %s" % (
            job["row"], record["status"], record.get("seconds") or 0.0,
            "" if record["status"] in DONE_STATUSES else " (exit %s)" % record.get("exit_code"), job["output"]))
    write_results(prefix, records)
    return records


def main(argv=None):
    p = argparse.ArgumentParser(prog="python3 -m mesohex.batch", description=__doc__.split("\n\n")[0],
                                formatter_class=argparse.RawDescriptionHelpFormatter,
                                epilog="Example: python3 -m mesohex.batch parts.csv --workers 4")
    p.add_argument("manifest", help="CSV with the header skeleton,surface,output[,options]")
    p.add_argument("--scheduler", help="address of a running Dask scheduler (default: a local cluster)")
    p.add_argument("--workers", type=int, default=2, help="worker processes of the local cluster (default 2)")
    p.add_argument("--results", help="results prefix: PREFIX.csv and PREFIX.json (default: MANIFEST.results)")
    p.add_argument("--timeout", type=float, default=3600.0, help="seconds per job before it is killed (default 3600)")
    p.add_argument("--retries", type=int, default=1,
                   help="retries of a job that crashed or timed out (default 1; bad input is not retried)")
    p.add_argument("--threads", type=int, default=-1,
                   help="threads per job (default: local cluster: cores / workers; scheduler: all cores)")
    p.add_argument("--mesohex", default=None, help="the mesohex executable (default: $MESOHEX_CLI, this build's, "
                                                   "or mesohex on PATH)")
    args = p.parse_args(argv)
    if args.workers < 1 or args.timeout <= 0 or args.retries < 0:
        p.error("--workers >= 1, --timeout > 0 and --retries >= 0")
    try:
        jobs = read_manifest(args.manifest)
    except ManifestError as e:
        print("mesohex.batch: error: %s" % e, file=sys.stderr)
        return 2
    prefix = args.results or os.path.splitext(args.manifest)[0] + ".results"
    cli = os.path.abspath(args.mesohex) if args.mesohex and os.sep in args.mesohex else (args.mesohex or default_cli())
    threads = args.threads
    if threads < 0:
        threads = max(1, (os.cpu_count() or 1) // args.workers) if not args.scheduler else 0

    from dask.distributed import Client, LocalCluster

    start = time.monotonic()
    if args.scheduler:
        cluster = None
        client = Client(args.scheduler)
    else:
        cluster = LocalCluster(n_workers=args.workers, threads_per_worker=1, processes=True, host="127.0.0.1",
                               dashboard_address=None)
        client = Client(cluster)
    try:
        records = run_batch(jobs, client, prefix, cli, args.timeout, args.retries, threads)
    finally:
        client.close()
        if cluster is not None:
            cluster.close()
    counts = {}
    for r in records.values():
        counts[r["status"]] = counts.get(r["status"], 0) + 1
    print("batch: %d jobs (%s) in %.1f s -> %s.csv, %s.json" % (
        len(jobs), ", ".join("%d %s" % (n, s) for s, n in sorted(counts.items())), time.monotonic() - start,
        prefix, prefix))
    return 0 if all(r["status"] in DONE_STATUSES for r in records.values()) else 1


if __name__ == "__main__":
    # Run the functions of the importable module `mesohex.batch` (not of __main__): the workers then unpickle run_job
    # by reference to it.
    from mesohex.batch import main as batch_main
    sys.exit(batch_main())

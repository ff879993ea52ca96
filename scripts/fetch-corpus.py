#!/usr/bin/env python3
"""Brings the third-party scenes of bench/corpus/manifest.json into real-scenes/ (git-ignored).

Their files are never committed (licences): this script fetches each source at the commit the
manifest pins, from the first place that has it:
  1. a local mirror: $LAMBERT_CORPUS_MIRROR/<owner>+<name>/repo, a bare git repository (or any
     git directory holding that commit), read with `git archive`;
  2. GitHub over HTTPS: https://raw.githubusercontent.com/<owner>/<name>/<commit>/<path>, one
     file at a time (folders are listed through the GitHub API).
Where neither works (no network, a file too large for the mirror) it says why and skips the
scenes that need it; the others are still fetched. Wrappers (scene files of this project that
light or frame a third-party model) are copied beside their source's files.

Prints one JSON document on stdout: {"corpus": DIR, "scenes": [{"id", "status", "path"|"reason"}]}.
Exit status 0 when it ran, whatever it skipped; 2 on a bad manifest.

    scripts/fetch-corpus.py [--manifest bench/corpus/manifest.json] [--out real-scenes] [--offline]
"""
import argparse
import io
import json
import os
import shutil
import subprocess
import sys
import tarfile
import urllib.error
import urllib.request

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def log(message):
    print(f"fetch-corpus: {message}", file=sys.stderr)


def from_mirror(source, destination):
    """Extracts the source's paths at its commit from a local git mirror. Returns None or why not."""
    mirror_root = os.environ.get("LAMBERT_CORPUS_MIRROR")
    if not mirror_root:
        return "no LAMBERT_CORPUS_MIRROR"
    git_dir = os.path.join(mirror_root, source["repo"].replace("/", "+"), "repo")
    if not os.path.isdir(git_dir):
        return f"no mirror at {git_dir}"
    # git archive stops at the first path it cannot read, so each path is archived on its own:
    # a mirror may lack its largest files and the rest is still useful.
    missing = []
    for path in source["paths"]:
        result = subprocess.run(["git", f"--git-dir={git_dir}", "archive", "--format=tar", source["commit"], path],
                                capture_output=True)
        if result.returncode != 0:
            missing.append(f"{path} ({result.stderr.decode(errors='replace').strip().splitlines()[-1:]})")
            continue
        with tarfile.open(fileobj=io.BytesIO(result.stdout)) as archive:
            try:
                archive.extractall(destination, filter="data")
            except TypeError:  # Python before 3.11.4 has no extraction filters; git archive writes plain files
                archive.extractall(destination)
    return f"the mirror lacks: {'; '.join(missing)}" if missing else None


def http_get(url, timeout=30):
    request = urllib.request.Request(url, headers={"User-Agent": "lambert-fetch-corpus"})
    with urllib.request.urlopen(request, timeout=timeout) as response:
        return response.read()


def from_github(source, destination):
    """Downloads the source's paths at its commit from GitHub. Returns None or why not."""
    owner_name, commit = source["repo"], source["commit"]
    files = []
    for path in source["paths"]:
        if os.path.splitext(path)[1]:
            files.append(path)
            continue
        # A folder: list it recursively through the trees API.
        try:
            tree = json.loads(http_get(f"https://api.github.com/repos/{owner_name}/git/trees/{commit}?recursive=1"))
        except (urllib.error.URLError, OSError, ValueError) as error:
            return f"GitHub unreachable ({error})"
        files += [entry["path"] for entry in tree.get("tree", [])
                  if entry["type"] == "blob" and entry["path"].startswith(path.rstrip("/") + "/")]
    for path in files:
        target = os.path.join(destination, path)
        if os.path.exists(target):
            continue
        try:
            data = http_get(f"https://raw.githubusercontent.com/{owner_name}/{commit}/{path}")
        except (urllib.error.URLError, OSError) as error:
            return f"GitHub unreachable for {path} ({error})"
        os.makedirs(os.path.dirname(target), exist_ok=True)
        with open(target + ".part", "wb") as out:
            out.write(data)
        os.replace(target + ".part", target)
    return None


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--manifest", default=os.path.join(ROOT, "bench/corpus/manifest.json"))
    parser.add_argument("--out", default=os.path.join(ROOT, "real-scenes"))
    parser.add_argument("--offline", action="store_true", help="use only the local mirror")
    args = parser.parse_args()
    try:
        with open(args.manifest) as f:
            manifest = json.load(f)
        sources, scenes = manifest["sources"], manifest["scenes"]
    except (OSError, ValueError, KeyError) as error:
        log(f"error: {args.manifest}: {error}")
        return 2

    problems = {}
    for name, source in sources.items():
        destination = os.path.join(args.out, name)
        os.makedirs(destination, exist_ok=True)
        if "local" in source:
            continue
        why = from_mirror(source, destination)
        if why and not args.offline:
            github_why = from_github(source, destination)
            why = None if github_why is None else f"{why}; {github_why}"
        if why:
            log(f"{name} ({source['repo']}): {why}")
            problems[name] = why

    report = []
    for scene in scenes:
        source = sources[scene["source"]]
        if "local" in source:
            path = os.path.join(ROOT, source["local"])
        else:
            folder = os.path.join(args.out, scene["source"])
            if "wrapper" in scene:
                shutil.copyfile(os.path.join(ROOT, scene["wrapper"]), os.path.join(folder, scene["file"]))
            path = os.path.join(folder, scene["file"])
        if os.path.exists(path):
            report.append({"id": scene["id"], "status": "ready", "path": path})
        else:
            reason = problems.get(scene["source"], "the file is not in the fetched source")
            log(f"skipping {scene['id']}: {reason}")
            report.append({"id": scene["id"], "status": "skipped", "reason": reason})
    ready = sum(1 for r in report if r["status"] == "ready")
    log(f"{ready} of {len(report)} scenes ready in {args.out}")
    json.dump({"corpus": args.out, "scenes": report}, sys.stdout, indent=1)
    print()
    return 0


if __name__ == "__main__":
    sys.exit(main())

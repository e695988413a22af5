"""Checks that the runtime stage of deploy/Containerfile installs every shared library the binaries load.

Usage: check_runtime_libraries.py CONTAINERFILE VSCAND VSCAN VSCAN_MESH_IMPORT RENDER_MESH

1. ldd of each binary: every library it resolves belongs to a Debian package that the runtime
   stage's `apt-get install` names, unless the package is part of the debian:12 base image.
2. Libraries opened with dlopen, which ldd cannot see: `vscan render` draws RENDER_MESH through the
   same headless EGL context the server's raster scanner uses (common/gl) with LD_DEBUG=files.
   Every object the loader dlopens (libglvnd's Mesa vendor library, the llvmpipe driver) must come
   from a named package; every other object it loads must come from a named package, the base
   image, or a dependency apt installs along with a named package.

The base image is derived from the dpkg database of this Debian 12 machine: the packages marked
Essential or Priority required (what debootstrap's minbase, the variant debian:12 is built from,
installs) together with everything they depend on.
"""

import os
import re
import subprocess
import sys
import tempfile

# The runtime stage is everything after the last FROM; RUN lines may continue with a backslash and
# hold comment lines, which the builder drops.
def runtime_packages(containerfile):
    with open(containerfile, encoding="utf-8") as f:
        lines = f.read().splitlines()
    starts = [i for i, line in enumerate(lines) if re.match(r"\s*FROM\s", line, re.IGNORECASE)]
    if not starts:
        sys.exit(f"{containerfile}: no FROM line")
    stage = [line for line in lines[starts[-1] + 1 :] if not line.lstrip().startswith("#")]
    instructions = re.sub(r"\\\n", " ", "\n".join(stage)).splitlines()
    packages = set()
    for instruction in instructions:
        if not re.match(r"\s*RUN\s", instruction, re.IGNORECASE):
            continue
        for command in re.split(r"&&|;|\|\|", instruction):
            words = command.split()
            if "apt-get" in words and "install" in words:
                packages.update(w for w in words[words.index("install") + 1 :] if not w.startswith("-"))
    if not packages:
        sys.exit(f"{containerfile}: the runtime stage installs no package with apt-get install")
    return packages


def dpkg_database():
    """Installed packages: name -> (essential, priority, dependency groups); virtual name -> providers."""
    out = subprocess.run(
        ["dpkg-query", "-W", "-f", "${Package}\t${Essential}\t${Priority}\t${Pre-Depends}\t${Depends}\t${Provides}\t"
         "${db:Status-Abbrev}\n"],
        check=True, capture_output=True, text=True).stdout
    packages, providers = {}, {}
    for row in out.splitlines():
        name, essential, priority, pre_depends, depends, provides, status = row.split("\t")
        if not status.startswith("ii"):
            continue
        groups = [group for group in (pre_depends + "," + depends).split(",") if group.strip()]
        packages[name] = (essential == "yes", priority, groups)
        for virtual in provides.split(","):
            if virtual.strip():
                providers.setdefault(bare_name(virtual), set()).add(name)
    return packages, providers


def bare_name(relation):
    """'libfoo:any (>= 1.2)' -> 'libfoo'."""
    return relation.strip().split(" ")[0].split(":")[0]


def dependency_closure(roots, packages, providers):
    """The installed packages apt brings in with roots (every installed alternative of each relation)."""
    seen, todo = set(), list(roots)
    while todo:
        name = todo.pop()
        if name in seen or name not in packages:
            continue
        seen.add(name)
        for group in packages[name][2]:
            for alternative in group.split("|"):
                target = bare_name(alternative)
                todo.extend([target] if target in packages else sorted(providers.get(target, ())))
    return seen


def path_variants(path):
    """The names dpkg may know a library by: as given, its /usr-merged twin, and the same for the real file."""
    variants = []
    for p in (path, os.path.realpath(path)):
        variants += [p, p[4:] if p.startswith("/usr/") else "/usr" + p]
    return variants


def owners(paths):
    """Library path -> the installed package that owns it (absent when none does), with one dpkg -S call."""
    variants = {path: path_variants(path) for path in paths}
    every = sorted({v for vs in variants.values() for v in vs})
    # dpkg -S exits 1 when some path has no owner; it still names the owners of the others.
    out = subprocess.run(["dpkg", "-S", *every], capture_output=True, text=True).stdout
    owner = {}
    for line in out.splitlines():
        if line.startswith("diversion ") or ": " not in line:
            continue
        package, _, owned = line.partition(": ")
        owner[owned.strip()] = package.split(",")[0].split(":")[0].strip()
    return {path: next(owner[v] for v in vs if v in owner) for path, vs in variants.items()
            if any(v in owner for v in vs)}


def ldd_libraries(binary):
    out = subprocess.run(["ldd", binary], check=True, capture_output=True, text=True).stdout
    libraries = []
    for line in out.splitlines():
        if "not found" in line:
            sys.exit(f"ldd {binary}: {line.strip()}")
        match = re.search(r"=>\s+(/\S+)", line)
        if match:
            libraries.append(match.group(1))
    if not libraries:
        sys.exit(f"ldd {binary} resolved no library: is it dynamically linked?")
    return libraries


def rendered_objects(vscan, mesh):
    """(every object loaded, the objects dlopened) while vscan render draws mesh through EGL."""
    with tempfile.TemporaryDirectory() as tmp:
        env = dict(os.environ, LD_DEBUG="files", LD_DEBUG_OUTPUT=os.path.join(tmp, "ld"))
        result = subprocess.run([vscan, "render", mesh, "-o", os.path.join(tmp, "out.png"), "--width", "32",
                                 "--height", "24"], env=env, capture_output=True, text=True)
        if result.returncode != 0:
            sys.exit(f"vscan render failed ({result.returncode}): {result.stderr.strip()}")
        log = "".join(open(os.path.join(tmp, f), encoding="utf-8", errors="replace").read()
                      for f in os.listdir(tmp) if f.startswith("ld."))
    loaded = set(re.findall(r"calling init: (/\S+)", log))
    opened = set(re.findall(r"opening file=(/\S+) \[", log))
    return loaded, opened & loaded


def check(named, facts):
    """The problems of a runtime stage that installs the packages named."""
    packages, providers, base, needed, loaded = facts
    brought_along = dependency_closure(named, packages, providers)
    problems = [f"the Containerfile names {p}, which is not a Debian package installed here"
                for p in sorted(named) if p not in packages]
    for package, why in sorted(needed.items()):
        if package not in named and package not in base:
            problems.append(f"{package} is not installed by the runtime stage; it provides {why}")
    for path, (package, dlopened) in sorted(loaded.items()):
        if dlopened and package not in named:
            problems.append(f"{package} is not installed by the runtime stage; {path} is dlopened while rendering")
        elif package not in named and package not in base and package not in brought_along and package not in needed:
            problems.append(f"{package} ({path}, loaded while rendering) comes with no package the runtime stage names")
    return problems


def main():
    if len(sys.argv) != 6:
        sys.exit(__doc__)
    containerfile, binaries, mesh = sys.argv[1], sys.argv[2:5], sys.argv[5]
    named = runtime_packages(containerfile)
    packages, providers = dpkg_database()
    base_roots = [name for name, (essential, priority, _) in packages.items() if essential or priority == "required"]
    base = dependency_closure(base_roots, packages, providers)
    for must in ("libc6", "libstdc++6", "libgcc-s1"):
        if must not in base:
            sys.exit(f"{must} is not in the derived base image: the dpkg database is not a Debian one")

    libraries = {binary: ldd_libraries(binary) for binary in binaries}
    paths, opened = rendered_objects(binaries[1], mesh)
    if not any("/dri/" in path for path in opened):
        sys.exit("vscan render loaded no Mesa DRI driver: the dlopen check has nothing to check")
    owner = owners({library for found in libraries.values() for library in found} | paths)

    needed, unowned = {}, []  # package -> the first library that needs it
    for binary in binaries:
        for library in libraries[binary]:
            package = owner.get(library)
            if package is None:
                unowned.append(f"{library} (needed by {os.path.basename(binary)}) belongs to no Debian package")
            else:
                needed.setdefault(package, f"{library} (ldd {os.path.basename(binary)})")
    loaded = {}  # path -> (package, dlopened); objects of no package are the binary itself
    for path in paths:
        package = owner.get(path)
        if package is not None:
            loaded[path] = (package, path in opened)
    facts = (packages, providers, base, needed, loaded)

    problems = unowned + check(named, facts)
    if problems:
        print("\n".join(problems))
        return 1

    # The check must notice a package taken out of the list: one each of those ldd and dlopen need.
    dlopened = sorted({package for package, was_opened in loaded.values() if was_opened})
    for package in [sorted(p for p in needed if p in named)[0]] + dlopened:
        if not any(package in problem for problem in check(named - {package}, facts)):
            print(f"a runtime stage without {package} passed the check: it checks nothing")
            return 1
    print(f"{len(needed)} packages behind ldd of {len(binaries)} binaries and {len(loaded)} objects loaded while "
          f"rendering (dlopened from {', '.join(dlopened)}): all installed by the runtime stage "
          f"({len(named)} named) or in the base image ({len(base)} packages); removing one is noticed")
    return 0


if __name__ == "__main__":
    sys.exit(main())

# Runs the lambert CLI as a separate process (a crash there cannot take Blender down), reads its
# progress lines and stops it on request. No bpy here: the add-on and the test both use it.
import os
import re
import shutil
import signal
import subprocess
import time

# Quality presets: the hierarchical method's link error (the CLI's --link-error, default 2e-4),
# the flat method's patch count (--patches, default 784).
LINK_ERROR = {'DRAFT': 1e-3, 'MEDIUM': 2e-4, 'HIGH': 5e-5}
PATCHES = {'DRAFT': 400, 'MEDIUM': 1600, 'HIGH': 6400}
# Lightmap texels per side (--lightmap-size, default 1024): lambert bakes about 35 000 texels a
# second on two cores, so a full 1024² atlas pair takes a minute.
LIGHTMAP_SIZE = {'DRAFT': 256, 'MEDIUM': 512, 'HIGH': 1024}

# lambert redraws "\rLABEL [####......]  42.0%" on a terminal (src/lambert/core/progress.cpp);
# an open-ended count is "\rLABEL 1234".
_PROGRESS = re.compile(r'([A-Za-z][A-Za-z ]*?)\s+\[[#.]*\]\s+([0-9.]+)%')
_COUNT = re.compile(r'([A-Za-z][A-Za-z ]*?)\s+([0-9]+)')


def find_binary(preference=''):
    """The lambert executable: the add-on preference, else $LAMBERT_BINARY, else `lambert` on PATH."""
    for candidate in (preference, os.environ.get('LAMBERT_BINARY', '')):
        if candidate:
            path = os.path.abspath(os.path.expanduser(candidate))
            if os.path.isfile(path) and os.access(path, os.X_OK):
                return path
            raise FileNotFoundError(f'lambert binary "{path}" (from the add-on preferences or $LAMBERT_BINARY) '
                                    'is not an executable file: build it (cmake --build build --target lambert_cli) '
                                    'and give build/bin/lambert')
    found = shutil.which('lambert')
    if not found:
        raise FileNotFoundError('no lambert binary: set it in Edit > Preferences > Add-ons > Lambert Bake, '
                                'or set $LAMBERT_BINARY, or put lambert on PATH')
    return found


def solve_arguments(binary, scene_glb, method, quality, output, out_path):
    """The command line: `lambert solve` on the exported glb with the preset's options.

    output 'VERTEX_COLORS' writes --export-vertices OUT.csv (position, normal, radiance per vertex);
    'LIGHTMAPS' writes --lightmaps --export OUT.glb (with OUT-lightmap-K.exr beside it)."""
    args = [binary, 'solve', '--scene', scene_glb, '--method', method.lower()]
    if method == 'HIERARCHICAL':
        args += ['--link-error', repr(LINK_ERROR[quality])]
    else:
        args += ['--patches', str(PATCHES[quality])]
    if output == 'VERTEX_COLORS':
        args += ['--export-vertices', out_path]
    else:
        args += ['--lightmaps', '--lightmap-size', str(LIGHTMAP_SIZE[quality]), '--export', out_path]
    # No --json: lambert draws progress only without it (and without --quiet).
    return args


class LambertProcess:
    """One run of lambert. Its stderr is a pseudo-terminal where the platform has one, so that
    lambert draws its progress lines (it draws them only on a terminal); stdout (the stats
    table) is a pipe."""

    def __init__(self, args):
        self.args = args
        self.progress_label = 'starting'
        self.progress_fraction = 0.0
        self._stderr_text = ''
        self._stdout_chunks = []
        self._master = None
        try:
            import pty
            self._master, slave = pty.openpty()
        except (ImportError, OSError):
            slave = subprocess.PIPE
        self.process = subprocess.Popen(args, stdin=subprocess.DEVNULL, stdout=subprocess.PIPE, stderr=slave,
                                        start_new_session=True)
        if self._master is not None:
            os.close(slave)
            os.set_blocking(self._master, False)
        os.set_blocking(self.process.stdout.fileno(), False)

    def _read_available(self):
        if self._master is not None:
            while True:
                try:
                    chunk = os.read(self._master, 65536)
                except (BlockingIOError, InterruptedError):
                    break
                except OSError:  # EIO: the process closed its end
                    break
                if not chunk:
                    break
                self._stderr_text += chunk.decode('utf-8', 'replace')
        elif self.process.stderr is not None:
            os.set_blocking(self.process.stderr.fileno(), False)
            chunk = self.process.stderr.read()
            if chunk:
                self._stderr_text += chunk.decode('utf-8', 'replace')
        try:
            chunk = self.process.stdout.read()
        except (BlockingIOError, InterruptedError):
            chunk = None
        if chunk:
            self._stdout_chunks.append(chunk)
        # The line being redrawn: the text after the last carriage return or newline that has some.
        segments = [t.strip() for t in re.split(r'[\r\n]', self._stderr_text[-400:]) if t.strip()]
        if segments:
            bar, count = _PROGRESS.fullmatch(segments[-1]), _COUNT.fullmatch(segments[-1])
            if bar:
                self.progress_label = bar.group(1).strip()
                self.progress_fraction = min(1.0, float(bar.group(2)) / 100.0)
            elif count:  # open-ended work (links judged): the count, no fraction
                self.progress_label = f'{count.group(1).strip()} {count.group(2)}'
                self.progress_fraction = 0.0

    def poll(self):
        """None while running, else the exit status."""
        self._read_available()
        return self.process.poll()

    def wait(self):
        """Waits for the exit, reading the output meanwhile (a full pipe or terminal buffer
        would block lambert)."""
        while self.poll() is None:
            time.sleep(0.05)
        return self.process.returncode

    def cancel(self):
        """Stops lambert (its whole process group) and waits until it is gone."""
        if self.process.poll() is None:
            try:
                os.killpg(self.process.pid, signal.SIGTERM)
            except ProcessLookupError:
                pass
            try:
                self.process.wait(5)
            except subprocess.TimeoutExpired:
                os.killpg(self.process.pid, signal.SIGKILL)
                self.process.wait()
        self.close()

    def close(self):
        if self._master is not None:
            os.close(self._master)
            self._master = None
        if self.process.stdout:
            self.process.stdout.close()

    def stdout(self):
        return b''.join(self._stdout_chunks).decode('utf-8', 'replace')

    def error_message(self):
        """lambert's own message: its stderr without the progress redraws."""
        lines = []
        for line in self._stderr_text.replace('\r\n', '\n').split('\n'):
            line = line.split('\r')[-1].strip()
            if line and not _PROGRESS.fullmatch(line) and not _COUNT.fullmatch(line):
                lines.append(line)
        return '\n'.join(lines) or f'lambert exited with status {self.process.returncode} and no message'

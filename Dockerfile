# motionsim: the simulation service in a slim image, run as a non-root user.
#   docker build -t motionsim .
#   docker run --rm -p 127.0.0.1:8000:8000 -p 127.0.0.1:1025:1025 -p 127.0.0.1:2323:2323 motionsim
# Ports come from the environment (MOTIONSIM_PORT, MOTIONSIM_PMAC_PORT, MOTIONSIM_TRIO_PORT);
# the HEALTHCHECK reads MOTIONSIM_PORT too, so change the port there:
#   docker run --rm -e MOTIONSIM_PORT=9000 -p 127.0.0.1:9000:9000 motionsim
# The working directory /opt/motionsim belongs to that user and holds examples/: `motionsim run
# examples/... --out DIR` and `motionsim serve --record FILE` write there (or into a volume).
# No registry? tools/docker_base_image.sh makes the base image from Debian packages;
# tools/docker_pip_context.py gives pip in the build this machine's CA bundle and index
# (`make docker-test` runs both).
FROM debian:bookworm-slim AS base

# MOTIONSIM_ALLOWED_HOSTS: the compose network reaches the service by its service name.
# PATH in full: an image made by `docker import` has none to extend.
ENV PYTHONDONTWRITEBYTECODE=1 \
    PYTHONUNBUFFERED=1 \
    MOTIONSIM_ALLOWED_HOSTS=motionsim \
    PIP_NO_CACHE_DIR=1 \
    PIP_DISABLE_PIP_VERSION_CHECK=1 \
    VIRTUAL_ENV=/opt/venv \
    PATH=/opt/venv/bin:/usr/local/sbin:/usr/local/bin:/usr/sbin:/usr/bin:/sbin:/bin

# Debian's Python 3.11 (the base image tools/docker_base_image.sh makes has it already).
RUN if ! python3 -c "import ensurepip, venv" 2>/dev/null; then \
        apt-get update \
        && DEBIAN_FRONTEND=noninteractive apt-get install -y --no-install-recommends \
           python3 python3-venv ca-certificates \
        && rm -rf /var/lib/apt/lists/*; \
    fi \
    && useradd --create-home --uid 10001 --shell /usr/sbin/nologin motionsim

# The dependencies, in a stage of their own fed by pyproject.toml and the build's pip settings
# (docker/pip/) alone: a source edit re-installs motionsim only (no re-download of FastAPI,
# numpy, ...), and the CA bundle pip used stays out of the final image.
FROM base AS deps
WORKDIR /tmp/build
COPY docker/pip/ /tmp/pip/
COPY pyproject.toml ./
RUN python3 -m venv /opt/venv
RUN python -c "import tomllib; t = tomllib.load(open('pyproject.toml', 'rb')); \
print('\n'.join(t['build-system']['requires'] + t['project']['dependencies']))" \
    > /tmp/requirements.txt \
    && PIP_CONFIG_FILE=/tmp/pip/pip.conf pip install -r /tmp/requirements.txt

FROM base
COPY --from=deps /opt/venv /opt/venv
# The package is built from /usr/src/motionsim and that copy removed: a source tree in the
# working directory would shadow the installed package for `python -m motionsim...` there.
COPY pyproject.toml README.md /usr/src/motionsim/
COPY motionsim /usr/src/motionsim/motionsim
COPY sim /usr/src/motionsim/sim
COPY app /usr/src/motionsim/app
COPY api /usr/src/motionsim/api
COPY examples /usr/src/motionsim/examples
RUN pip install --no-deps --no-build-isolation /usr/src/motionsim \
    && rm -rf /usr/src/motionsim
WORKDIR /opt/motionsim
COPY examples ./examples
RUN chown -R motionsim:motionsim /opt/motionsim

USER motionsim

# REST + WebSocket, PMAC Ethernet protocol, Trio command line (23 is privileged: use 2323).
ENV MOTIONSIM_HOST=0.0.0.0 \
    MOTIONSIM_PORT=8000 \
    MOTIONSIM_PMAC_PORT=1025 \
    MOTIONSIM_TRIO_PORT=2323
EXPOSE 8000 1025 2323

# -P: the working directory is not put on sys.path, so whatever is mounted or written there
# (a checkout's motionsim/ folder) cannot shadow the installed package.
HEALTHCHECK --interval=10s --timeout=3s --start-period=10s --retries=3 \
    CMD ["python", "-P", "-m", "motionsim.app.healthcheck"]

CMD ["motionsim", "serve"]

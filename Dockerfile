# motionsim: the simulation service in a slim image, run as a non-root user.
#   docker build -t motionsim .
#   docker run --rm -p 127.0.0.1:8000:8000 -p 127.0.0.1:1025:1025 -p 127.0.0.1:2323:2323 motionsim
# Ports come from the environment (MOTIONSIM_PORT, MOTIONSIM_PMAC_PORT, MOTIONSIM_TRIO_PORT);
# the HEALTHCHECK reads MOTIONSIM_PORT too, so change the port there:
#   docker run --rm -e MOTIONSIM_PORT=9000 -p 127.0.0.1:9000:9000 motionsim
# The working directory /opt/motionsim belongs to that user: `motionsim run ... --out DIR` and
# `motionsim serve --record FILE` write there (or into a mounted volume).
FROM python:3.11-slim

# MOTIONSIM_ALLOWED_HOSTS: the compose network reaches the service by its service name.
ENV PYTHONDONTWRITEBYTECODE=1 \
    PYTHONUNBUFFERED=1 \
    MOTIONSIM_ALLOWED_HOSTS=motionsim \
    PIP_NO_CACHE_DIR=1 \
    PIP_DISABLE_PIP_VERSION_CHECK=1

RUN useradd --create-home --uid 10001 --shell /usr/sbin/nologin motionsim

WORKDIR /opt/motionsim
# Dependencies first, in a layer of their own: it is rebuilt only when pyproject.toml changes,
# so editing the source re-installs motionsim alone (no re-download of FastAPI, numpy, ...).
COPY pyproject.toml ./
RUN python -c "import tomllib; t = tomllib.load(open('pyproject.toml', 'rb')); \
print('\n'.join(t['build-system']['requires'] + t['project']['dependencies']))" \
    > /tmp/requirements.txt \
    && pip install -r /tmp/requirements.txt \
    && rm /tmp/requirements.txt
COPY README.md ./
COPY motionsim ./motionsim
COPY sim ./sim
COPY app ./app
COPY api ./api
COPY examples ./examples
RUN pip install --no-deps --no-build-isolation . \
    && rm -rf build ./*.egg-info \
    && chown -R motionsim:motionsim /opt/motionsim

USER motionsim

# REST + WebSocket, PMAC Ethernet protocol, Trio command line (23 is privileged: use 2323).
ENV MOTIONSIM_HOST=0.0.0.0 \
    MOTIONSIM_PORT=8000 \
    MOTIONSIM_PMAC_PORT=1025 \
    MOTIONSIM_TRIO_PORT=2323
EXPOSE 8000 1025 2323

HEALTHCHECK --interval=10s --timeout=3s --start-period=10s --retries=3 \
    CMD ["python", "-m", "motionsim.app.healthcheck"]

CMD ["motionsim", "serve"]

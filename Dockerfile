# motionsim: the simulation service in a slim image, run as a non-root user.
#   docker build -t motionsim .
#   docker run --rm -p 8000:8000 -p 1025:1025 -p 2323:2323 motionsim
FROM python:3.11-slim

# MOTIONSIM_ALLOWED_HOSTS: the compose network reaches the service by its service name.
ENV PYTHONDONTWRITEBYTECODE=1 \
    PYTHONUNBUFFERED=1 \
    MOTIONSIM_ALLOWED_HOSTS=motionsim \
    PIP_NO_CACHE_DIR=1 \
    PIP_DISABLE_PIP_VERSION_CHECK=1

WORKDIR /opt/motionsim
COPY pyproject.toml README.md ./
COPY motionsim ./motionsim
COPY sim ./sim
COPY app ./app
COPY api ./api
COPY examples ./examples
RUN pip install . \
    && useradd --create-home --uid 10001 --shell /usr/sbin/nologin motionsim

USER motionsim

# REST + WebSocket, PMAC Ethernet protocol, Trio command line (23 is privileged: use 2323).
EXPOSE 8000 1025 2323

HEALTHCHECK --interval=10s --timeout=3s --start-period=10s --retries=3 \
    CMD ["python", "-c", "import sys, urllib.request; sys.exit(0 if urllib.request.urlopen('http://127.0.0.1:8000/health', timeout=2).status == 200 else 1)"]

CMD ["motionsim", "serve", "--host", "0.0.0.0", "--port", "8000", "--pmac-port", "1025", "--trio-port", "2323"]

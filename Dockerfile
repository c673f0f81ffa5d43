# syntax=docker/dockerfile:1
# isotrace in a container: a multi-stage build on Debian bookworm. The
# runtime image has the release binary and Mesa's CPU Vulkan driver
# (lavapipe), so it renders on any node without a GPU.
#
#   docker build -t isotrace .
#   docker run --rm -v "$PWD/out:/out" isotrace render @tangle --size 512 -o /out/tangle.png
#
# examples/batch/k8s-job.yaml runs it as a Kubernetes Indexed Job.

# --- build: the toolchain the repository is tested with (edition 2024) ---
FROM rust:1.95-bookworm AS build
WORKDIR /src
# Everything `cargo build` reads: the manifest and lock file, the sources,
# the templates and examples the binary embeds, and the bench targets the
# manifest declares.
COPY Cargo.toml Cargo.lock ./
COPY src ./src
COPY templates ./templates
COPY examples ./examples
COPY grammar ./grammar
COPY benches ./benches
RUN cargo build --release --locked --bin isotrace \
    && strip target/release/isotrace

# --- runtime: Debian bookworm with lavapipe ---
FROM debian:bookworm-slim
# Bookworm's Mesa is 22.3.6, the lavapipe isotrace is tested with. Exact
# Debian revisions are not pinned: a security update replaces them.
# hadolint ignore=DL3008
RUN apt-get update \
    && apt-get install -y --no-install-recommends mesa-vulkan-drivers libvulkan1 \
    && rm -rf /var/lib/apt/lists/*
COPY --from=build /src/target/release/isotrace /usr/local/bin/isotrace
# Mesa's device-select layer warns on every start without this.
ENV NODEVICE_SELECT=1
# Mesa keeps its shader cache in $HOME/.cache: a non-root user with a home,
# named by its number so Kubernetes' runAsNonRoot can check it.
RUN useradd --create-home --uid 10001 --user-group isotrace
USER 10001:10001
ENV HOME=/home/isotrace
WORKDIR /home/isotrace
ENTRYPOINT ["isotrace"]
CMD ["--help"]

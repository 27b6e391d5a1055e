# vkpath on Debian 12 (bookworm): lavapipe (Mesa's CPU Vulkan driver) and Intel Open Image
# Denoise, set up by the same script as a checkout (scripts/install-deps.sh).
#
#   docker build -t vkpath .
#   docker run --rm -v "$PWD:/work" vkpath render -o /work/cornell.png
#
# CI does not build this image (no Docker there): README.md ("Docker") has the manual check.
# On a machine with an NVIDIA GPU, the NVIDIA Container Toolkit (`docker run --gpus all`,
# with NVIDIA_DRIVER_CAPABILITIES=graphics,compute) brings the driver's Vulkan ICD in and
# vkpath prefers the GPU over lavapipe.

FROM rust:1.89-bookworm AS build
WORKDIR /src
COPY . .
# The Debian packages vkpath builds against, and OIDN into /opt/vkpath-oidn; then the binary
# into /usr/local/bin, as `cargo install --path .` puts it into ~/.cargo/bin.
RUN bash scripts/install-deps.sh \
    && cargo install --locked --path . --root /usr/local

FROM debian:bookworm-slim
# What the binary needs at run time: the Vulkan loader and lavapipe (shaderc and glslang are
# linked statically; OIDN is loaded from /opt/vkpath-oidn when --denoise asks for it).
RUN apt-get update \
    && DEBIAN_FRONTEND=noninteractive apt-get install -y --no-install-recommends \
       libvulkan1 mesa-vulkan-drivers \
    && rm -rf /var/lib/apt/lists/*
COPY --from=build /opt/vkpath-oidn /opt/vkpath-oidn
COPY --from=build /usr/local/bin/vkpath /usr/local/bin/vkpath
WORKDIR /work
ENTRYPOINT ["vkpath"]
CMD ["--help"]

# The `uniphys` binary (API, workers, migrations, CLI) in one image; docker-compose.yml and
# deploy/k8s run it with different commands. Build: docker build -t uniphys .
FROM rust:1.95-bookworm AS build
# npm fetches three.js for the dashboard at build time (crates/service/uniphys_dashboard/build.rs).
RUN apt-get update && apt-get install -y --no-install-recommends nodejs npm \
    && rm -rf /var/lib/apt/lists/*
WORKDIR /src
COPY . .
RUN cargo build --release --locked --bin uniphys

FROM debian:bookworm-slim
RUN apt-get update && apt-get install -y --no-install-recommends ca-certificates \
    && rm -rf /var/lib/apt/lists/* && useradd --system --uid 10001 uniphys
COPY --from=build /src/target/release/uniphys /usr/local/bin/uniphys
USER uniphys
WORKDIR /home/uniphys
ENTRYPOINT ["uniphys"]

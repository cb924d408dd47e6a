# damfem: commands for a fresh Debian machine.
#   make demo   installs what is missing, builds in release mode and runs `damfem safety` on the dam of
#               geo/dam_combinations.toml (three load combinations) into out/dam
#   make test   installs what is missing and runs the whole test suite
#   make test-quick  the unit tests, the bad-input tests and a few end-to-end runs (about a
#               minute once built); make test stays the suite that must pass
#   make bench-peers  also installs Debian's python3-getfem and times damfem against GetFEM on
#               Scene A at about 1e4 and 1e5 unknowns (LARGE=1: also 5e5), damfem from the same
#               .msh and from the .geo (nested iteration); not part of make test
# Each installation step runs only when something is missing, so a second run is fast.

APT_PACKAGES := libgmsh-dev gmsh libclang-dev libgl1 libegl1 libegl-mesa0 libgl1-mesa-dri fonts-dejavu-core \
	libpetsc-real-dev openmpi-bin pkg-config
VENV := .venv
PYTHON := $(VENV)/bin/python
SUDO := $(shell [ "$$(id -u)" -eq 0 ] || echo sudo)

.PHONY: demo test test-quick bench-peers bench-peers-solid getfem rust deps apt-deps python-deps build

demo: rust deps build
	./target/release/damfem safety geo/dam_combinations.toml -o out/dam; code=$$?; [ $$code -eq 0 ] || [ $$code -eq 3 ]
	$(PYTHON) scripts/render.py out/dam/usual/dam_combinations.pvd out/dam/usual/dam.png
	$(PYTHON) scripts/render.py out/dam/usual/dam_combinations.pvd out/dam/usual/heel.png --field sigma_yy --edges --box -5 20 -8 8
	@echo "results in out/dam: report.md and safety.json for the three load combinations, one directory"
	@echo "  per combination with its report.md, base_stresses.png, joint.csv and the .pvd of its adaptive"
	@echo "  run (for ParaView); pictures out/dam/usual/dam.png (von Mises) and heel.png (sigma_yy near the heel)"
	@echo "  (exit 3 of damfem safety: a combination does not hold, which report.md states)"

test: rust deps build
	cargo test --release
	DAMFEM=$(CURDIR)/target/release/damfem $(PYTHON) -m pytest -q tests/python

QUICK_END_TO_END := input:: cli::every_scene_checks cli::help_texts cli::adapt_writes_every_step \
	joint::friction_keys joint::combinations_override joint::an_earthquake joint::silt_and_ice \
	joint::safety_runs_every_load_combination joint::safety_reports_a_combination_that_does_not_hold

test-quick: rust deps build
	cargo test --release --lib
	cargo test --release --test unit
	cargo test --release --test end_to_end -- $(QUICK_END_TO_END)
	DAMFEM=$(CURDIR)/target/release/damfem $(PYTHON) -m pytest -q tests/python/test_docs.py tests/python/test_crack_rules.py

bench-peers: rust apt-deps getfem build
	/usr/bin/python3 scripts/bench_peers.py $(if $(LARGE),--large)

bench-peers-solid: rust apt-deps getfem build
	/usr/bin/python3 scripts/bench_peers_solid.py $(if $(LARGE),--sizes 2e4 1e5 4e5)

getfem:
	@dpkg-query -W -f='$${Status}' python3-getfem 2>/dev/null | grep -q "install ok installed" || { \
	  echo "installing Debian packages: python3-getfem"; \
	  $(SUDO) apt-get update -qq && \
	  DEBIAN_FRONTEND=noninteractive $(SUDO) apt-get install -y -qq --no-install-recommends python3-getfem; }

rust:
	@command -v cargo >/dev/null 2>&1 || { \
	  echo "error: cargo not found: install Rust and cargo (https://rustup.rs), open a new shell, then run make again" >&2; \
	  exit 1; }

deps: apt-deps python-deps

build:
	cargo build --release

apt-deps:
	@missing=""; for p in $(APT_PACKAGES); do \
	  dpkg-query -W -f='$${Status}' $$p 2>/dev/null | grep -q "install ok installed" || missing="$$missing $$p"; \
	done; \
	python3 -c "import venv, ensurepip" 2>/dev/null || missing="$$missing python3-venv"; \
	if [ -n "$$missing" ]; then \
	  echo "installing Debian packages:$$missing"; \
	  $(SUDO) apt-get update -qq && \
	  DEBIAN_FRONTEND=noninteractive $(SUDO) apt-get install -y -qq --no-install-recommends $$missing; \
	fi

python-deps: $(VENV)/.installed

$(VENV)/.installed: requirements.txt
	python3 -m venv $(VENV)
	$(VENV)/bin/pip install -q --upgrade pip
	$(VENV)/bin/pip install -q -r requirements.txt
	touch $@

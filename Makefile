# vprof — the two commands a new user needs:
#   make run    install what is missing, build, generate the profile for examples/limits.pb
#   make test   install what is missing, run every test (hspec, goldens, clients, interop)
#   make test-fast  the inner loop: every hspec spec with 50 cases a property, no daemon suites
# and for the figures:
#   make bench  criterion benchmarks (bench/), and bench/compare against Ruckig
#   make compare-kinematics  closed-form and numerical IK beside EAIK, roboticstoolbox, TRAC-IK
#   make compare-compress  path compression beside TD-TR, the optimal subset, a free LS fit and the floor
#   make load EXAMPLE=F.pb  requests/s and latency of `vprof serve` at 1, 8 and 64 connections

STACK ?= stack
# a fixed QuickCheck seed keeps CI reproducible; VPROF_SEED=random explores new cases
VPROF_SEED ?= 42
SEED_ARG := $(if $(filter random,$(VPROF_SEED)),,--seed $(VPROF_SEED))

.PHONY: all deps build run test test-fast test-metamorphic hspec check-examples bench compare compare-kinematics load clean
all: build

deps:
	@scripts/install-deps.sh

build: deps
	$(STACK) build

run: build
	$(STACK) exec vprof -- examples/limits.pb

hspec: deps
	$(STACK) test --test-arguments='$(SEED_ARG)'

# about a minute once built: every spec with 50 cases a property (VPROF_PROPERTY_CASES),
# without the daemon's robustness suites (their sockets dominate the time) and clients
test-fast: deps
	VPROF_PROPERTY_CASES=50 $(STACK) test --test-arguments='$(SEED_ARG) --skip Robustness --skip VProf.Server --skip VProf.Service'

# the properties of the generator over the wide world of requests (test/VProf/Profile/WideSpec.hs,
# the metamorphic ones among them) with more cases than `make test`'s 1000 a property
WIDE_CASES ?= 5000
test-metamorphic: deps
	VPROF_PROPERTY_CASES=$(WIDE_CASES) $(STACK) test --test-arguments='$(SEED_ARG) --match "wide world"'

# every example through the CLI as CSV, checked by an independent Python checker (and a 0.87 mm
# request in proto3 JSON's lowerCamelCase: its end tolerance is a tenth of the route, the
# contract's default for a route under 10 cm, and with 1 cm its first sample would be a crawl);
# and the checker itself must reject a profile broken on purpose; every command whose standard
# output is full (/dev/full) exits 2 saying so
check-examples: build
	@set -e; tmp=$$(mktemp -d); \
	for f in examples/*.json; do \
	  $(STACK) exec vprof -- $$f --format csv -o $$tmp/p.csv > /dev/null; \
	  python3 tools/check_csv.py $$f $$tmp/p.csv; \
	done; \
	printf '{"routeLength": 0.00087, "speedLimits": [{"startDistance": 0, "velocity": 0.69}], "minAcceleration": -0.37, "maxAcceleration": 0.37, "minJerk": -0.0139, "maxJerk": 87.8, "timeStep": 0.05, "startAcceleration": -0.04}' > $$tmp/camel.json; \
	$(STACK) exec vprof -- $$tmp/camel.json --format csv -o $$tmp/p.csv > /dev/null; \
	python3 tools/check_csv.py $$tmp/camel.json $$tmp/p.csv; \
	$(STACK) exec vprof -- examples/simple.json --format csv -o $$tmp/p.csv > /dev/null; \
	awk -F, 'NR==20{$$3=$$3+0.5} {print}' OFS=, $$tmp/p.csv > $$tmp/broken.csv; \
	if python3 tools/check_csv.py examples/simple.json $$tmp/broken.csv > /dev/null; then \
	  echo "check_csv.py accepted a broken profile"; exit 1; else echo "check_csv.py rejects a broken profile: ok"; fi; \
	$(STACK) exec vprof -- check examples/simple.json $$tmp/p.csv; \
	if $(STACK) exec vprof -- check examples/simple.json $$tmp/broken.csv > /dev/null; then \
	  echo "vprof check accepted a broken profile"; exit 1; else echo "vprof check rejects a broken profile: ok"; fi; \
	if [ -w /dev/full ]; then \
	  for args in "examples/simple.json" "check examples/simple.json $$tmp/p.csv" "robots" "fk ur5 0 0 0 0 0 0" \
	              "compress examples/freiburg-40.csv --points 10" "select examples/cell-task.yaml --robots ur5" \
	              "plan examples/plan-square.csv --robot ur5 --format csv"; do \
	    rc=0; $(STACK) exec vprof -- $$args > /dev/full 2> $$tmp/err || rc=$$?; \
	    if [ $$rc != 2 ] || ! grep -q "cannot write" $$tmp/err; then \
	      echo "vprof $$args > /dev/full: exit $$rc, not 2 with 'cannot write':"; cat $$tmp/err; exit 1; fi; \
	  done; echo "a full standard output is exit 2, said, for every command: ok"; fi; \
	rm -rf $$tmp

include mk/daemon.mk

test: hspec check-examples golden-check interop
	@echo "make test: all suites passed"

bench: build
	$(STACK) bench vprof:bench:vprof-bench --benchmark-arguments='--output bench/report.html'

# the daemon under load (bench/run-load: the C++ load tool, 10 s a level)
EXAMPLE ?= examples/route-abcd.pb
load: build
	bench/run-load "$$($(STACK) path --local-install-root)/bin/vprof" $(EXAMPLE)

compare: build
	@python3 -c 'import ruckig' 2>/dev/null || python3 -m pip install -q ruckig
	python3 bench/compare

# vprof's kinematics beside EAIK, roboticstoolbox-python and TRAC-IK (bench/KINEMATICS.md): makes its
# own bench/.venv and an -O2 build of its driver under .stack-work-bench; no test depends on it
compare-kinematics:
	python3 bench/compare-kinematics

.PHONY: compare-compress
compare-compress:
	python3 bench/compare-compress

clean:
	$(STACK) clean
	rm -rf clients/cpp/build clients/python/vprof_client/gen

# robot selection: the thesis experiment through vprof and through roboticstoolbox + fcl, and
# vprof select over the library; writes bench/SELECT.md (makes bench/.venv if missing)
compare-select:
	python3 bench/compare-select

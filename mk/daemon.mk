# Daemon / clients / golden targets (issue 3). The top-level Makefile can `include mk/daemon.mk`
# and add `daemon-check` to `make test` (after `stack test`, which runs the hspec specs).
#
# Needs: protobuf-compiler libprotobuf-dev pkg-config g++ (apt), protobuf==4.21.12 (pip).
VPROF_BIN ?= $(shell stack path --local-install-root 2>/dev/null)/bin/vprof
STUB_BIN  ?= $(shell stack path --local-install-root 2>/dev/null)/bin/vprof-stub-daemon

.PHONY: clients golden-check interop interop-stub daemon-check fuzz

clients:                 ## C++ client + load tool, Python generated code
	$(MAKE) -C clients/cpp all load
	python3 -c "import sys; sys.path.insert(0, 'clients/python'); import vprof_client._gen as g; g.generate(force=True)"

golden-check:            ## regenerate test/golden/*.bin with protoc's Python into a temp dir; fail on drift
	python3 test/golden/make_golden.py --check

interop: clients         ## both clients against the REAL `vprof serve` (needs the generator)
	clients/run-interop.sh $(VPROF_BIN)

interop-stub: clients    ## both clients against vprof-stub-daemon (transport only)
	VPROF_STUB=1 clients/run-interop.sh $(STUB_BIN)

daemon-check: golden-check interop-stub interop

fuzz:                    ## outside CI: 10^5 mutated frames
	python3 bench/fuzz.py --daemon $(STUB_BIN) --frames 100000

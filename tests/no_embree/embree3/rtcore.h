// Put first on the include path by scripts/test-port-alone.sh: any file of the port's build
// that reaches for Embree (the oracle's ray caster) stops here.
#error "Embree included from the port's build: gpu/ must stand on common/ alone"

#define _GNU_SOURCE
#include <dlfcn.h>
#include <stdio.h>
#include <stdlib.h>
#include <stdatomic.h>
static void *lib(void) { static void *h; if (!h) h = dlopen("/var/tmp/peers/lib/python3.11/site-packages/mitsuba/libembree3.so", RTLD_NOW | RTLD_NOLOAD); return h; }
static atomic_long rays_i, rays_o, calls_i, calls_o, single_i, single_o;
typedef void (*f16)(const int*, void*, void*, void*);
typedef void (*f1)(void*, void*, void*);
static long lanes(const int *v) { long n = 0; for (int i = 0; i < 16; i++) n += v[i] != 0; return n; }
void _ZN7mitsuba14rtcIntersect16EPKiPNS_10RTCSceneTyEPNS_19RTCIntersectContextEPNS_11RTCRayHit16E(const int *v, void *s, void *c, void *r) {
    static f16 real; if (!real) real = (f16)dlsym(lib(), "_ZN7mitsuba14rtcIntersect16EPKiPNS_10RTCSceneTyEPNS_19RTCIntersectContextEPNS_11RTCRayHit16E");
    atomic_fetch_add(&rays_i, lanes(v)); atomic_fetch_add(&calls_i, 1); real(v, s, c, r);
}
void _ZN7mitsuba13rtcOccluded16EPKiPNS_10RTCSceneTyEPNS_19RTCIntersectContextEPNS_8RTCRay16E(const int *v, void *s, void *c, void *r) {
    static f16 real; if (!real) real = (f16)dlsym(lib(), "_ZN7mitsuba13rtcOccluded16EPKiPNS_10RTCSceneTyEPNS_19RTCIntersectContextEPNS_8RTCRay16E");
    atomic_fetch_add(&rays_o, lanes(v)); atomic_fetch_add(&calls_o, 1); real(v, s, c, r);
}
void _ZN7mitsuba13rtcIntersect1EPNS_10RTCSceneTyEPNS_19RTCIntersectContextEPNS_9RTCRayHitE(void *s, void *c, void *r) {
    static f1 real; if (!real) real = (f1)dlsym(lib(), "_ZN7mitsuba13rtcIntersect1EPNS_10RTCSceneTyEPNS_19RTCIntersectContextEPNS_9RTCRayHitE");
    atomic_fetch_add(&single_i, 1); real(s, c, r);
}
void _ZN7mitsuba12rtcOccluded1EPNS_10RTCSceneTyEPNS_19RTCIntersectContextEPNS_6RTCRayE(void *s, void *c, void *r) {
    static f1 real; if (!real) real = (f1)dlsym(lib(), "_ZN7mitsuba12rtcOccluded1EPNS_10RTCSceneTyEPNS_19RTCIntersectContextEPNS_6RTCRayE");
    atomic_fetch_add(&single_o, 1); real(s, c, r);
}
__attribute__((destructor)) static void report(void) {
    fprintf(stderr, "RAYCOUNT intersect16 calls %ld lanes %ld; occluded16 calls %ld lanes %ld; intersect1 %ld occluded1 %ld\n",
            calls_i, rays_i, calls_o, rays_o, single_i, single_o);
}

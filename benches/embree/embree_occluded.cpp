// Traces the shadow rays of an envshadow ray dump (`envshadow bench --dump-rays DIR`, format in
// src/raydump.rs) with Embree 3 occlusion queries, one ray at a time (rtcOccluded1) and in
// bundles of 16 consecutive rays (rtcOccluded16), over 1..N threads that take chunks of the
// dump's chunk size in order from a shared counter, as `envshadow bench --replay` does.
// Prints a markdown row per mode and thread count: seconds (median), M rays/s, occluded rays.
//
// Built by scripts/compare-embree.sh; not part of the renderer's build.
#include <embree3/rtcore.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <string>
#include <thread>
#include <vector>

struct Dump {
  std::vector<float> tris;  // 9 per triangle
  std::vector<float> rays;  // 6 per ray
  uint32_t chunk = 4096;
};

static bool read_dump(const char* path, Dump& d) {
  FILE* f = std::fopen(path, "rb");
  if (!f) {
    std::fprintf(stderr, "%s: cannot open\n", path);
    return false;
  }
  char magic[8];
  uint32_t ntri = 0, chunk = 0;
  uint64_t nray = 0;
  bool ok = std::fread(magic, 1, 8, f) == 8 && std::memcmp(magic, "ESRAYS1\0", 8) == 0 &&
            std::fread(&ntri, 4, 1, f) == 1 && std::fread(&chunk, 4, 1, f) == 1 &&
            std::fread(&nray, 8, 1, f) == 1 && chunk > 0;
  if (ok) {
    d.chunk = chunk;
    d.tris.resize(size_t(ntri) * 9);
    d.rays.resize(size_t(nray) * 6);
    ok = std::fread(d.tris.data(), 4, d.tris.size(), f) == d.tris.size() &&
         std::fread(d.rays.data(), 4, d.rays.size(), f) == d.rays.size();
  }
  std::fclose(f);
  if (!ok) std::fprintf(stderr, "%s: not a ray dump (bad header or truncated)\n", path);
  return ok;
}

static uint64_t trace_chunk1(RTCScene scene, const float* r, size_t n) {
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  uint64_t blocked = 0;
  for (size_t i = 0; i < n; ++i, r += 6) {
    RTCRay ray;
    ray.org_x = r[0]; ray.org_y = r[1]; ray.org_z = r[2];
    ray.dir_x = r[3]; ray.dir_y = r[4]; ray.dir_z = r[5];
    ray.tnear = 0.0f;
    ray.tfar = std::numeric_limits<float>::infinity();
    ray.time = 0.0f; ray.mask = 0xffffffff; ray.id = 0; ray.flags = 0;
    rtcOccluded1(scene, &ctx, &ray);
    blocked += ray.tfar < 0.0f;
  }
  return blocked;
}

static uint64_t trace_chunk16(RTCScene scene, const float* r, size_t n) {
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  ctx.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
  uint64_t blocked = 0;
  alignas(64) RTCRay16 ray;
  alignas(64) int valid[16];
  for (size_t base = 0; base < n; base += 16) {
    size_t m = std::min<size_t>(16, n - base);
    for (size_t k = 0; k < 16; ++k) {
      const float* q = r + 6 * (base + std::min(k, m - 1));
      valid[k] = k < m ? -1 : 0;
      ray.org_x[k] = q[0]; ray.org_y[k] = q[1]; ray.org_z[k] = q[2];
      ray.dir_x[k] = q[3]; ray.dir_y[k] = q[4]; ray.dir_z[k] = q[5];
      ray.tnear[k] = 0.0f;
      ray.tfar[k] = std::numeric_limits<float>::infinity();
      ray.time[k] = 0.0f; ray.mask[k] = 0xffffffff; ray.id[k] = 0; ray.flags[k] = 0;
    }
    rtcOccluded16(valid, scene, &ctx, &ray);
    for (size_t k = 0; k < m; ++k) blocked += ray.tfar[k] < 0.0f;
  }
  return blocked;
}

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: %s DUMP [threads,...] [repeat]\n", argv[0]);
    return 2;
  }
  Dump d;
  if (!read_dump(argv[1], d)) return 2;
  std::vector<int> threads;
  std::string list = argc > 2 ? argv[2] : "1,2";
  for (size_t p = 0; p < list.size();) {
    size_t q = list.find(',', p);
    if (q == std::string::npos) q = list.size();
    threads.push_back(std::max(1, std::atoi(list.substr(p, q - p).c_str())));
    p = q + 1;
  }
  int repeat = argc > 3 ? std::max(1, std::atoi(argv[3])) : 3;

  RTCDevice device = rtcNewDevice(nullptr);
  if (!device) {
    std::fprintf(stderr, "embree: cannot create a device\n");
    return 1;
  }
  RTCScene scene = rtcNewScene(device);
  RTCGeometry geom = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
  size_t ntri = d.tris.size() / 9;
  float* v = (float*)rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                             3 * sizeof(float), ntri * 3);
  std::memcpy(v, d.tris.data(), d.tris.size() * sizeof(float));
  unsigned* idx = (unsigned*)rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0,
                                                     RTC_FORMAT_UINT3, 3 * sizeof(unsigned), ntri);
  for (size_t i = 0; i < ntri * 3; ++i) idx[i] = unsigned(i);
  rtcCommitGeometry(geom);
  rtcAttachGeometry(scene, geom);
  rtcReleaseGeometry(geom);
  auto t0 = std::chrono::steady_clock::now();
  rtcCommitScene(scene);
  double build = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  size_t nray = d.rays.size() / 6;
  std::printf("embree %d.%d.%d: %zu triangles (BVH built in %.3f s), %zu rays, chunks of %u, "
              "median of %d\n\n",
              RTC_VERSION_MAJOR, RTC_VERSION_MINOR, RTC_VERSION_PATCH, ntri, build, nray, d.chunk,
              repeat);
  std::printf("| tracer | threads | s | M rays/s | occluded |\n|---|---:|---:|---:|---:|\n");
  for (int bundle : {1, 16}) {
    for (int nt : threads) {
      std::vector<double> times;
      uint64_t blocked = 0;
      for (int rep = 0; rep < repeat; ++rep) {
        std::atomic<size_t> next{0};
        std::atomic<uint64_t> total{0};
        auto work = [&]() {
          uint64_t b = 0;
          for (;;) {
            size_t c = next.fetch_add(1);
            size_t start = c * d.chunk;
            if (start >= nray) break;
            size_t n = std::min<size_t>(d.chunk, nray - start);
            const float* r = d.rays.data() + 6 * start;
            b += bundle == 1 ? trace_chunk1(scene, r, n) : trace_chunk16(scene, r, n);
          }
          total += b;
        };
        auto t = std::chrono::steady_clock::now();
        std::vector<std::thread> pool;
        for (int k = 1; k < nt; ++k) pool.emplace_back(work);
        work();
        for (auto& th : pool) th.join();
        times.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count());
        blocked = total;
      }
      std::sort(times.begin(), times.end());
      double s = times[times.size() / 2];
      std::printf("| embree rtcOccluded%d | %d | %.3f | %.2f | %llu |\n", bundle, nt, s,
                  nray / s / 1e6, (unsigned long long)blocked);
    }
  }
  rtcReleaseScene(scene);
  rtcReleaseDevice(device);
  return 0;
}

// pgt oracles: the code cgal_sqrt3 and openmesh_sqrt3 share. A strict OFF reader and an exact
// OFF writer in double (both libraries' own readers either round through float or accept more
// than we want to compare), the command line, the timing loop and the one JSON line.
//
// Usage: <tool>_sqrt3 IN.off K OUT.off [--repeat R]   (OUT.off "-": time only, write nothing)
// Exit codes: 0 success, 2 bad arguments or bad input, 1 anything else.
#ifndef PGT_ORACLE_COMMON_HPP
#define PGT_ORACLE_COMMON_HPP

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <fstream>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <malloc.h>

namespace pgt_oracle {

// Bad arguments or bad input: exit code 2. Everything else that throws: exit code 1.
struct Input_error : std::runtime_error {
    using std::runtime_error::runtime_error;
};

// A face a library refuses to add; run() prefixes the file and line.
struct Face_error : Input_error {
    Face_error(std::size_t face_, const std::string &why)
        : Input_error("face " + std::to_string(face_) + ": " + why), face(face_) {}
    std::size_t face;
};

struct Tri_mesh {
    std::vector<double> xyz;          // 3 per vertex
    std::vector<std::uint32_t> tri;   // 3 per face, counter-clockwise
    std::vector<std::size_t> line;    // input line of each face (for messages)
    std::size_t vertex_count() const { return xyz.size() / 3; }
    std::size_t face_count() const { return tri.size() / 3; }
};

// Both libraries index with 32 bits; this also bounds K (faces grow by 3 per iteration).
constexpr std::uint64_t max_elements = 0x7fffffffu;

inline std::string where(const std::string &path, std::size_t line) {
    return path + ":" + std::to_string(line) + ": ";
}

// Splits one line into whitespace-separated tokens, dropping a '#' comment and a trailing '\r'.
inline void tokenize(const char *b, const char *e, std::vector<std::string> &out) {
    out.clear();
    const char *hash = static_cast<const char *>(std::memchr(b, '#', static_cast<size_t>(e - b)));
    if (hash) e = hash;
    while (b < e) {
        while (b < e && std::isspace(static_cast<unsigned char>(*b))) ++b;
        const char *s = b;
        while (b < e && !std::isspace(static_cast<unsigned char>(*b))) ++b;
        if (b > s) out.emplace_back(s, b);
    }
}

inline bool parse_u64(const std::string &s, std::uint64_t &out) {
    if (s.empty() || s[0] == '-' || s[0] == '+') return false;
    errno = 0;
    char *end = nullptr;
    unsigned long long v = std::strtoull(s.c_str(), &end, 10);
    if (errno || *end) return false;
    out = v;
    return true;
}

inline bool parse_double(const std::string &s, double &out) {
    errno = 0;
    char *end = nullptr;
    double v = std::strtod(s.c_str(), &end);
    if (end == s.c_str() || *end || errno == ERANGE || !std::isfinite(v)) return false;
    out = v;
    return true;
}

// Plain OFF: "OFF" (counts may follow on the same line), '#' comments, "V F E", V lines "x y z",
// F lines "3 i j k". Anything else (COFF/NOFF, colours, polygons, bad or repeated indices,
// vertices used by no face, extra lines) throws Input_error naming the file and line.
inline Tri_mesh read_off(const std::string &path) {
    std::ifstream f(path, std::ios::binary);
    if (!f) throw Input_error(path + ": cannot open for reading: " + std::strerror(errno));
    std::stringstream ss;
    ss << f.rdbuf();
    const std::string text = ss.str();

    enum { header, counts, vertices, faces, done } state = header;
    std::uint64_t nv = 0, nf = 0;
    Tri_mesh m;
    std::vector<std::string> tok;
    std::size_t lineno = 0, pos = 0;
    while (pos < text.size()) {
        std::size_t nl = text.find('\n', pos);
        if (nl == std::string::npos) nl = text.size();
        ++lineno;
        tokenize(text.data() + pos, text.data() + nl, tok);
        pos = nl + 1;
        if (tok.empty()) continue;
        const std::string at = where(path, lineno);
        switch (state) {
        case header:
            if (tok[0] != "OFF")
                throw Input_error(at + "expected the header \"OFF\" (only plain OFF is supported), "
                                       "found \"" + tok[0] + "\"");
            tok.erase(tok.begin());
            state = counts;
            if (tok.empty()) break;
            [[fallthrough]];
        case counts: {
            std::uint64_t ne = 0;
            if (tok.size() != 3 || !parse_u64(tok[0], nv) || !parse_u64(tok[1], nf) ||
                !parse_u64(tok[2], ne))
                throw Input_error(at + "expected the counts \"V F E\" as three integers");
            if (nv == 0 || nf == 0) throw Input_error(at + "the mesh has no vertices or no faces");
            if (nv > max_elements || nf > max_elements)
                throw Input_error(at + "too many vertices or faces (limit 2^31-1)");
            // Each vertex line takes at least 6 bytes, each face line at least 8: reject
            // absurd counts before reserving memory for them.
            if (nv * 6 + nf * 8 > text.size() + 16)
                throw Input_error(at + "the counts " + tok[0] + " " + tok[1] +
                                  " do not fit in a file of " + std::to_string(text.size()) +
                                  " bytes");
            m.xyz.reserve(nv * 3);
            m.tri.reserve(nf * 3);
            m.line.reserve(nf);
            state = vertices;
            break;
        }
        case vertices: {
            double p[3];
            if (tok.size() != 3 || !parse_double(tok[0], p[0]) || !parse_double(tok[1], p[1]) ||
                !parse_double(tok[2], p[2]))
                throw Input_error(at + "vertex " + std::to_string(m.vertex_count()) +
                                  ": expected three finite numbers \"x y z\" and nothing else");
            m.xyz.insert(m.xyz.end(), p, p + 3);
            if (m.vertex_count() == nv) state = faces;
            break;
        }
        case faces: {
            const std::string face = "face " + std::to_string(m.face_count()) + ": ";
            std::uint64_t n = 0, idx[3];
            if (!parse_u64(tok[0], n))
                throw Input_error(at + face + "expected the vertex count, found \"" + tok[0] + "\"");
            if (n != 3)
                throw Input_error(at + face + "has " + tok[0] +
                                  " vertices; only triangles are supported");
            if (tok.size() != 4)
                throw Input_error(at + face + "expected \"3 i j k\" and nothing else");
            for (int k = 0; k < 3; ++k)
                if (!parse_u64(tok[k + 1], idx[k]) || idx[k] >= nv)
                    throw Input_error(at + face + "vertex index \"" + tok[k + 1] +
                                      "\" is not in [0, " + std::to_string(nv) + ")");
            if (idx[0] == idx[1] || idx[1] == idx[2] || idx[0] == idx[2])
                throw Input_error(at + face + "repeats a vertex");
            for (int k = 0; k < 3; ++k) m.tri.push_back(static_cast<std::uint32_t>(idx[k]));
            m.line.push_back(lineno);
            if (m.face_count() == nf) state = done;
            break;
        }
        case done:
            throw Input_error(at + "unexpected data after the " + std::to_string(nf) + " faces");
        }
    }
    if (state != done)
        throw Input_error(path + ": unexpected end of file: read " +
                          std::to_string(m.vertex_count()) + " of " + std::to_string(nv) +
                          " vertices and " + std::to_string(m.face_count()) + " of " +
                          std::to_string(nf) + " faces");
    // Sqrt(3) is not defined on a vertex without faces (the two libraries leave such vertices in
    // place by different code paths), so the oracles refuse them rather than compare them.
    std::vector<char> used(m.vertex_count(), 0);
    for (std::uint32_t v : m.tri) used[v] = 1;
    for (std::size_t v = 0; v < used.size(); ++v)
        if (!used[v])
            throw Input_error(path + ": vertex " + std::to_string(v) + " is used by no face");
    return m;
}

// Writes OFF with 17 significant digits, so that doubles round-trip exactly.
inline void write_off(const std::string &path, const Tri_mesh &m) {
    std::FILE *f = std::fopen(path.c_str(), "wb");
    if (!f) throw std::runtime_error(path + ": cannot open for writing: " + std::strerror(errno));
    std::vector<char> buf(1 << 20);
    std::setvbuf(f, buf.data(), _IOFBF, buf.size());
    std::fprintf(f, "OFF\n%zu %zu 0\n", m.vertex_count(), m.face_count());
    for (std::size_t v = 0; v < m.vertex_count(); ++v)
        std::fprintf(f, "%.17g %.17g %.17g\n", m.xyz[3 * v], m.xyz[3 * v + 1], m.xyz[3 * v + 2]);
    for (std::size_t t = 0; t < m.face_count(); ++t)
        std::fprintf(f, "3 %u %u %u\n", static_cast<unsigned>(m.tri[3 * t]),
                     static_cast<unsigned>(m.tri[3 * t + 1]), static_cast<unsigned>(m.tri[3 * t + 2]));
    const bool bad = std::ferror(f) != 0;
    if (std::fclose(f) != 0 || bad) throw std::runtime_error(path + ": write failed");
}

// Backend concept:
//   void build(const Tri_mesh &in);  // a fresh mesh from the arrays; Face_error if rejected
//   void subdivide(int k);           // the timed call
//   Tri_mesh extract() const;        // vertices and faces in the mesh's iteration order
template <class Backend> int run(int argc, char **argv, const char *tool) {
    // The benchmark allocator policy, the same in every timed program (pgt bench sets it too):
    // freed memory stays in the heap, so repeated runs time the algorithm rather than the
    // kernel's first-touch page faults on fresh mmapped blocks (about 45 % of a 2.7M-face run
    // on these VMs).
    mallopt(M_MMAP_MAX, 0);
    mallopt(M_TRIM_THRESHOLD, 1 << 30);
    const std::string usage = std::string("usage: ") + tool + "_sqrt3 IN.off K OUT.off [--repeat R]";
    try {
        std::vector<std::string> pos;
        std::uint64_t repeat = 0; // 0: a single run without warm-up
        for (int i = 1; i < argc; ++i) {
            const std::string a = argv[i];
            if (a == "--repeat") {
                if (i + 1 >= argc || !parse_u64(argv[i + 1], repeat) || repeat < 1 || repeat > 100000)
                    throw Input_error("--repeat needs an integer R >= 1\n" + usage);
                ++i;
            } else if (a.size() > 1 && a[0] == '-') {
                throw Input_error("unknown option \"" + a + "\"\n" + usage);
            } else {
                pos.push_back(a);
            }
        }
        if (pos.size() != 3) throw Input_error(usage);
        std::uint64_t k = 0;
        if (!parse_u64(pos[1], k) || k > 40)
            throw Input_error("K must be an integer in [0, 40], found \"" + pos[1] + "\"\n" + usage);

        const Tri_mesh in = read_off(pos[0]);
        std::uint64_t faces_out = in.face_count();
        for (std::uint64_t i = 0; i < k; ++i)
            if ((faces_out *= 3) > max_elements)
                throw Input_error(pos[0] + ": " + std::to_string(in.face_count()) +
                                  " faces subdivided " + pos[1] +
                                  " times exceed the limit of 2^31-1 faces");

        const std::uint64_t runs = repeat ? repeat : 1;
        std::vector<double> ms;
        std::unique_ptr<Backend> mesh;
        for (std::uint64_t r = 0; r < runs + (repeat ? 1 : 0); ++r) {
            mesh.reset(); // free the previous copy before building the next
            mesh = std::make_unique<Backend>();
            try {
                mesh->build(in); // not timed
            } catch (const Face_error &e) {
                throw Input_error(where(pos[0], in.line.at(e.face)) + e.what());
            }
            const auto t0 = std::chrono::steady_clock::now();
            mesh->subdivide(static_cast<int>(k));
            const auto t1 = std::chrono::steady_clock::now();
            if (repeat && r == 0) continue; // warm-up
            ms.push_back(std::chrono::duration<double, std::milli>(t1 - t0).count());
        }
        const Tri_mesh out = mesh->extract();
        if (pos[2] != "-") write_off(pos[2], out);

        std::vector<double> sorted = ms;
        std::sort(sorted.begin(), sorted.end());
        const std::size_t n = sorted.size();
        const double median = n % 2 ? sorted[n / 2] : 0.5 * (sorted[n / 2 - 1] + sorted[n / 2]);
        std::printf("{\"tool\":\"%s\",\"vertices_in\":%zu,\"faces_in\":%zu,\"iterations\":%u,"
                    "\"vertices_out\":%zu,\"faces_out\":%zu,\"median_ms\":%.3f,\"best_ms\":%.3f,"
                    "\"runs\":%zu}\n",
                    tool, in.vertex_count(), in.face_count(), static_cast<unsigned>(k),
                    out.vertex_count(), out.face_count(), median, sorted[0], n);
        return std::fflush(stdout) == 0 ? 0 : 1;
    } catch (const Input_error &e) {
        std::fprintf(stderr, "%s_sqrt3: %s\n", tool, e.what());
        return 2;
    } catch (const std::exception &e) {
        std::fprintf(stderr, "%s_sqrt3: %s\n", tool, e.what());
        return 1;
    } catch (...) {
        std::fprintf(stderr, "%s_sqrt3: unknown exception\n", tool);
        return 1;
    }
}

} // namespace pgt_oracle

#endif

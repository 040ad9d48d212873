// The steps of ReadMesh after a format's check, shared by every format: the
// polygons split into triangle fans, the triangles that repeat a vertex or
// duplicate an earlier one dropped, the coordinates checked finite. Each
// works in fixed chunks of vertices or faces (ChunkItems of
// options.items_per_chunk) on options.num_threads threads; a chunk writes only
// its own outputs, and what chunks find (counts, the first bad polygon) is
// combined in chunk order, so the mesh, the counts and the messages are the
// same for any thread count and chunk size.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "msdeform/core/mesh_io_formats.h"

namespace msdeform {
namespace {

// True when polygon p of `soup` has at least 3 vertices, all in range.
bool PolygonIsValid(const PolygonSoup& soup, int p) {
  const int* ids = soup.face_ids.data() + soup.face_offsets[p];
  const int size = soup.face_offsets[p + 1] - soup.face_offsets[p];
  if (size < 3) return false;
  const int num_vertices = soup.num_vertices();
  for (int k = 0; k < size; ++k) {
    if (ids[k] < 0 || ids[k] >= num_vertices) return false;
  }
  return true;
}

// The message for polygon p, which PolygonIsValid refused.
std::string DescribeInvalidPolygon(const PolygonSoup& soup, int p) {
  const int* ids = soup.face_ids.data() + soup.face_offsets[p];
  const int size = soup.face_offsets[p + 1] - soup.face_offsets[p];
  std::ostringstream message;
  if (size < 3) {
    message << "face " << p << " has " << size << " vertices; need at least 3";
    return message.str();
  }
  for (int k = 0; k < size; ++k) {
    if (ids[k] < 0 || ids[k] >= soup.num_vertices()) {
      message << "face " << p << " refers to vertex " << ids[k] << ", outside 0.."
              << soup.num_vertices() - 1;
      break;
    }
  }
  return message.str();
}

// Exclusive prefix sums of `counts` in place; returns the total.
long long PrefixSums(std::vector<long long>* counts) {
  long long total = 0;
  for (long long& count : *counts) {
    const long long here = count;
    count = total;
    total += here;
  }
  return total;
}

}  // namespace

bool ConcatenateSoupPieces(const std::vector<SoupPiece*>& pieces, int num_threads,
                           PolygonSoup* soup) {
  if (pieces.size() == 1) {
    soup->xyz = std::move(pieces[0]->xyz);
    soup->face_offsets = std::move(pieces[0]->face_offsets);
    soup->face_ids = std::move(pieces[0]->face_ids);
    return true;
  }
  // Where each piece's coordinates, polygons and ids start.
  const size_t n = pieces.size();
  std::vector<size_t> xyz_start(n + 1, 0), polygon_start(n + 1, 0), id_start(n + 1, 0);
  for (size_t c = 0; c < n; ++c) {
    xyz_start[c + 1] = xyz_start[c] + pieces[c]->xyz.size();
    polygon_start[c + 1] = polygon_start[c] + pieces[c]->face_offsets.size() - 1;
    id_start[c + 1] = id_start[c] + pieces[c]->face_ids.size();
  }
  constexpr size_t kIntMax = static_cast<size_t>(std::numeric_limits<int>::max());
  if (id_start[n] > kIntMax || polygon_start[n] > kIntMax) return false;
  soup->xyz.resize(xyz_start[n]);
  soup->face_offsets.resize(polygon_start[n] + 1);
  soup->face_offsets[0] = 0;
  soup->face_ids.resize(id_start[n]);
  ForEachTask(static_cast<int>(n), num_threads, [&](int c) {
    SoupPiece& piece = *pieces[c];
    std::copy(piece.xyz.begin(), piece.xyz.end(), soup->xyz.begin() + xyz_start[c]);
    std::copy(piece.face_ids.begin(), piece.face_ids.end(), soup->face_ids.begin() + id_start[c]);
    const int shift = static_cast<int>(id_start[c]);
    for (size_t p = 1; p < piece.face_offsets.size(); ++p) {
      soup->face_offsets[polygon_start[c] + p] = piece.face_offsets[p] + shift;
    }
    piece = SoupPiece();
  });
  return true;
}

bool SplitIntoTriangles(const PolygonSoup& soup, const MeshReadOptions& options, Mesh* mesh,
                        std::string* problem) {
  const int threads = options.num_threads;
  const int num_vertices = soup.num_vertices();
  const int num_polygons = soup.num_polygons();
  const long long per = ChunkItems(num_polygons, options.items_per_chunk);
  const int chunks = NumChunks(num_polygons, per);
  // Each chunk's triangles, or -1 - (its first invalid polygon).
  std::vector<long long> triangles(chunks, 0);
  ForEachTask(chunks, threads, [&](int c) {
    const int end = static_cast<int>(std::min<long long>(num_polygons, (c + 1) * per));
    long long count = 0;
    for (int p = static_cast<int>(c * per); p < end; ++p) {
      if (!PolygonIsValid(soup, p)) {
        triangles[c] = -1 - p;
        return;
      }
      count += soup.face_offsets[p + 1] - soup.face_offsets[p] - 2;
    }
    triangles[c] = count;
  });
  for (int c = 0; c < chunks; ++c) {
    if (triangles[c] < 0) {
      *problem = DescribeInvalidPolygon(soup, static_cast<int>(-1 - triangles[c]));
      return false;
    }
  }
  const long long num_triangles = PrefixSums(&triangles);  // now each chunk's first

  mesh->vertices.resize(3, num_vertices);
  const long long vertex_per = ChunkItems(num_vertices, options.items_per_chunk);
  ForEachTask(NumChunks(num_vertices, vertex_per), threads, [&](int c) {
    const long long begin = c * vertex_per;
    const long long end = std::min<long long>(num_vertices, begin + vertex_per);
    std::memcpy(mesh->vertices.data() + 3 * begin, soup.xyz.data() + 3 * begin,
                sizeof(double) * 3 * (end - begin));
  });
  mesh->faces.resize(3, num_triangles);
  ForEachTask(chunks, threads, [&](int c) {
    const int end = static_cast<int>(std::min<long long>(num_polygons, (c + 1) * per));
    long long t = triangles[c];
    for (int p = static_cast<int>(c * per); p < end; ++p) {
      const int* ids = soup.face_ids.data() + soup.face_offsets[p];
      const int size = soup.face_offsets[p + 1] - soup.face_offsets[p];
      for (int k = 1; k + 1 < size; ++k) mesh->faces.col(t++) << ids[0], ids[k], ids[k + 1];
    }
  });
  return true;
}

namespace {

// A triangle with its key: its ids rotated to start at the lowest.
struct KeyedFace {
  std::array<int, 3> key;
  int face;
};

// Marks in `drop` the duplicates among one block's triangles, in_block[0 ..
// count) (file order), whose lowest ids are first_vertex ..
// first_vertex + block_vertices - 1, and returns how many. Triangles are
// grouped by their lowest id (a counting sort, file order within a group);
// duplicates are within a group. A group is scanned pairwise when small and
// sorted by the other two ids (stable: the earliest first) when large, so a
// vertex in a huge fan costs n log n, not n^2.
int MarkDuplicatesInBlock(const KeyedFace* in_block, int count, int first_vertex,
                          int block_vertices, UninitializedVector<char>* drop_out) {
  UninitializedVector<char>& drop = *drop_out;
  std::vector<int> start(block_vertices + 1, 0);
  for (int i = 0; i < count; ++i) ++start[in_block[i].key[0] - first_vertex + 1];
  for (int v = 0; v < block_vertices; ++v) start[v + 1] += start[v];
  std::vector<KeyedFace> grouped(count);
  {
    std::vector<int> fill(start.begin(), start.end() - 1);
    for (int i = 0; i < count; ++i) {
      grouped[fill[in_block[i].key[0] - first_vertex]++] = in_block[i];
    }
  }
  constexpr int kScanLimit = 16;
  int found = 0;
  for (int v = 0; v < block_vertices; ++v) {
    const auto first = grouped.begin() + start[v], last = grouped.begin() + start[v + 1];
    if (last - first > kScanLimit) {
      std::stable_sort(first, last,
                       [](const KeyedFace& f, const KeyedFace& g) { return f.key < g.key; });
      for (auto it = first + 1; it < last; ++it) {
        if (it->key == (it - 1)->key) {
          drop[it->face] = 1;
          ++found;
        }
      }
      continue;
    }
    for (auto it = first + 1; it < last; ++it) {
      for (auto earlier = first; earlier < it; ++earlier) {
        if (!drop[earlier->face] && it->key == earlier->key) {
          drop[it->face] = 1;
          ++found;
          break;
        }
      }
    }
  }
  return found;
}

}  // namespace

// Duplicates are found among the triangles with the same lowest id. They are
// grouped in two steps: by block of lowest ids (a stable scatter in face
// chunks, each with its own row of block counts), then within each block by
// the lowest id itself (a counting sort), so each group lists its triangles
// in file order, as one counting sort over all of them did. A triangle
// travels with its key, so a block's work reads only the block's entries.
void DropDegenerateAndDuplicateFaces(const MeshReadOptions& options, Mesh* mesh,
                                     MeshReadReport* report) {
  const int threads = options.num_threads;
  const int num_faces = mesh->num_faces();
  const int num_vertices = mesh->num_vertices();
  const long long face_per = ChunkItems(num_faces, options.items_per_chunk);
  const int face_chunks = NumChunks(num_faces, face_per);
  const long long block_per = ChunkItems(num_vertices, options.items_per_chunk);
  const int blocks = NumChunks(num_vertices, block_per);
  auto face_range = [&](int c, int* begin, int* end) {
    *begin = static_cast<int>(c * face_per);
    *end = static_cast<int>(std::min<long long>(num_faces, (c + 1) * face_per));
  };
  // Triangle f rotated to start at its lowest id: one key for the three
  // rotations of (a, b, c), another for the opposite orientation (a, c, b).
  // False for a triangle that repeats a vertex.
  auto key_of = [mesh](int f, std::array<int, 3>* key) {
    const int a = mesh->faces(0, f), b = mesh->faces(1, f), c = mesh->faces(2, f);
    if (a == b || b == c || a == c) return false;
    const int first = a < b ? (a < c ? 0 : 2) : (b < c ? 1 : 2);
    *key = {mesh->faces(first, f), mesh->faces((first + 1) % 3, f),
            mesh->faces((first + 2) % 3, f)};
    return true;
  };

  UninitializedVector<char> drop(num_faces);
  // Per face chunk: its triangles that repeat a vertex, and its row of
  // counts per block (then where its triangles of each block go).
  std::vector<int> degenerate(face_chunks, 0);
  std::vector<int> slot(static_cast<size_t>(face_chunks) * blocks, 0);
  ForEachTask(face_chunks, threads, [&](int c) {
    int begin, end;
    face_range(c, &begin, &end);
    // Counted apart and stored once: the rows of neighbouring chunks share
    // cache lines.
    std::vector<int> row(blocks, 0);
    int repeats = 0;
    std::array<int, 3> key;
    for (int f = begin; f < end; ++f) {
      const bool valid = key_of(f, &key);
      drop[f] = !valid;
      if (valid) {
        ++row[key[0] / block_per];
      } else {
        ++repeats;
      }
    }
    std::copy(row.begin(), row.end(), slot.begin() + static_cast<size_t>(c) * blocks);
    degenerate[c] = repeats;
  });
  for (int count : degenerate) report->dropped_degenerate_faces += count;

  // Blocks in order, and within a block the chunks in order.
  std::vector<int> block_start(blocks + 1, 0);
  int running = 0;
  for (int b = 0; b < blocks; ++b) {
    block_start[b] = running;
    for (int c = 0; c < face_chunks; ++c) {
      int& entry = slot[static_cast<size_t>(c) * blocks + b];
      const int count = entry;
      entry = running;
      running += count;
    }
  }
  block_start[blocks] = running;
  UninitializedVector<KeyedFace> by_block(running);
  ForEachTask(face_chunks, threads, [&](int c) {
    int begin, end;
    face_range(c, &begin, &end);
    std::vector<int> row(slot.begin() + static_cast<size_t>(c) * blocks,
                         slot.begin() + static_cast<size_t>(c + 1) * blocks);
    KeyedFace entry;
    for (int f = begin; f < end; ++f) {
      if (!key_of(f, &entry.key)) continue;
      entry.face = f;
      by_block[row[entry.key[0] / block_per]++] = entry;
    }
  });

  // The duplicates, block by block.
  std::vector<int> duplicates(blocks, 0);
  ForEachTask(blocks, threads, [&](int b) {
    const int first_vertex = static_cast<int>(b * block_per);
    const int block_vertices =
        static_cast<int>(std::min<long long>(num_vertices, first_vertex + block_per)) -
        first_vertex;
    duplicates[b] = MarkDuplicatesInBlock(by_block.data() + block_start[b],
                                          block_start[b + 1] - block_start[b], first_vertex,
                                          block_vertices, &drop);
  });
  UninitializedVector<KeyedFace>().swap(by_block);
  int dropped = 0;
  for (int b = 0; b < blocks; ++b) dropped += duplicates[b];
  report->dropped_duplicate_faces += dropped;
  for (int count : degenerate) dropped += count;
  if (dropped == 0) return;

  // The kept triangles, in order, into a new matrix (chunk c's go after
  // those of the chunks before it).
  std::vector<long long> kept(face_chunks, 0);
  ForEachTask(face_chunks, threads, [&](int c) {
    int begin, end;
    face_range(c, &begin, &end);
    long long count = 0;
    for (int f = begin; f < end; ++f) count += !drop[f];
    kept[c] = count;
  });
  const long long num_kept = PrefixSums(&kept);
  Eigen::Matrix3Xi faces(3, num_kept);
  ForEachTask(face_chunks, threads, [&](int c) {
    int begin, end;
    face_range(c, &begin, &end);
    long long k = kept[c];
    for (int f = begin; f < end; ++f) {
      if (!drop[f]) faces.col(k++) = mesh->faces.col(f);
    }
  });
  mesh->faces.swap(faces);
}

bool AllVerticesFinite(const Mesh& mesh, const MeshReadOptions& options) {
  const int num_vertices = mesh.num_vertices();
  const long long per = ChunkItems(num_vertices, options.items_per_chunk);
  const int chunks = NumChunks(num_vertices, per);
  std::vector<char> finite(chunks, 1);
  ForEachTask(chunks, options.num_threads, [&](int c) {
    const double* xyz = mesh.vertices.data() + 3 * c * per;
    const long long size = 3 * (std::min<long long>(num_vertices, (c + 1) * per) - c * per);
    bool all = true;
    for (long long i = 0; i < size; ++i) all &= std::isfinite(xyz[i]);
    finite[c] = all;
  });
  return std::all_of(finite.begin(), finite.end(), [](char f) { return f != 0; });
}

}  // namespace msdeform

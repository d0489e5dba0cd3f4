#include "mass_spring_cloth/contact_broad_phase.hpp"

#include <algorithm>

#include "shellflow/geometry/mesh_edges.hpp"

namespace shellflow::cloth {

namespace {

// Below this many triangles the loops run serially: a parallel region costs more.
constexpr int kParallelThreshold = 2048;

}  // namespace

void ContactBroadPhase::set_topology(const std::vector<std::array<int, 3>>& triangles,
                                     int cloth_nodes, bool self_collision,
                                     const Vectors& rest_positions) {
  m_triangles = triangles;
  m_cloth_nodes = cloth_nodes;
  m_self = self_collision;
  const int triangle_count = static_cast<int>(triangles.size());
  int node_count = 0;
  for (const auto& t : triangles) node_count = std::max({node_count, t[0] + 1, t[1] + 1, t[2] + 1});

  // Each edge is owned by the first triangle that has it.
  const geometry::MeshEdges mesh(triangles);
  m_edges = mesh.edges;
  std::vector<std::vector<int>> owned_edges(triangle_count), owned_nodes(triangle_count);
  for (int e = 0; e < static_cast<int>(m_edges.size()); ++e)
    owned_edges[mesh.edge_triangles[mesh.edge_start[e]]].push_back(e);
  std::vector<int> node_owner(node_count, -1);
  for (int t = 0; t < triangle_count; ++t)
    for (int k : triangles[t])
      if (node_owner[k] < 0) {
        node_owner[k] = t;
        owned_nodes[t].push_back(k);
      }
  m_node_start.assign(1, 0);
  m_edge_start.assign(1, 0);
  m_owned_nodes.clear();
  m_owned_edges.clear();
  for (int t = 0; t < triangle_count; ++t) {
    m_owned_nodes.insert(m_owned_nodes.end(), owned_nodes[t].begin(), owned_nodes[t].end());
    m_owned_edges.insert(m_owned_edges.end(), owned_edges[t].begin(), owned_edges[t].end());
    m_node_start.push_back(static_cast<int>(m_owned_nodes.size()));
    m_edge_start.push_back(static_cast<int>(m_owned_edges.size()));
  }
  m_cloth_triangles.clear();
  m_obstacle_triangles.clear();
  for (int t = 0; t < triangle_count; ++t) {
    const auto& tri = triangles[t];
    const bool obstacle = tri[0] >= cloth_nodes && tri[1] >= cloth_nodes && tri[2] >= cloth_nodes;
    (obstacle ? m_obstacle_triangles : m_cloth_triangles).push_back(t);
  }
  std::vector<std::array<int, 3>> cloth;
  for (int t : m_cloth_triangles) cloth.push_back(triangles[t]);
  if (m_hierarchy.empty() || cloth != m_hierarchy.triangles())
    m_hierarchy.build(cloth, rest_positions);
}

void ContactBroadPhase::find(const Vectors& a, const Vectors& b, double distance,
                             ContactCandidates& out) {
  out.point_triangle.clear();
  out.edge_edge.clear();
  const int triangle_count = static_cast<int>(m_triangles.size());
  if (triangle_count == 0) return;
  const int node_count = static_cast<int>(a.size());
  const int edge_count = static_cast<int>(m_edges.size());
  const double pad = 0.5 * distance;
  m_node_boxes.resize(node_count);
  m_edge_boxes.resize(edge_count);
  m_triangle_boxes.resize(triangle_count);
#pragma omp parallel if (triangle_count > kParallelThreshold)
  {
#pragma omp for schedule(static)
    for (int k = 0; k < node_count; ++k)
      m_node_boxes[k] =
          geometry::Aabb(a[k].cwiseMin(b[k]).array() - pad, a[k].cwiseMax(b[k]).array() + pad);
#pragma omp for schedule(static) nowait
    for (int e = 0; e < edge_count; ++e) {
      m_edge_boxes[e] = m_node_boxes[m_edges[e][0]];
      m_edge_boxes[e].extend(m_node_boxes[m_edges[e][1]]);
    }
#pragma omp for schedule(static)
    for (int t = 0; t < triangle_count; ++t) {
      const auto& tri = m_triangles[t];
      m_triangle_boxes[t] = m_node_boxes[tri[0]];
      m_triangle_boxes[t].extend(m_node_boxes[tri[1]]);
      m_triangle_boxes[t].extend(m_node_boxes[tri[2]]);
    }
  }

  // Overlapping triangle pairs: the cloth's own (unless self-collision is off), then
  // each other solid's triangle against the cloth.
  const int cloth_count = static_cast<int>(m_cloth_triangles.size());
  m_cloth_boxes.resize(cloth_count);
  for (int c = 0; c < cloth_count; ++c) m_cloth_boxes[c] = m_triangle_boxes[m_cloth_triangles[c]];
  m_culled_patches = 0;
  m_triangle_pairs.clear();
  if (m_self) {
    m_hierarchy.update(m_cloth_boxes, a, b);
    m_culled_patches = m_hierarchy.self_pairs(a, b, distance, m_triangle_pairs);
  } else {
    m_hierarchy.refit(m_cloth_boxes);  // the normal cones serve only self-collision
  }
  for (auto& pair : m_triangle_pairs)
    pair = {m_cloth_triangles[pair[0]], m_cloth_triangles[pair[1]]};
  const int obstacle_count = static_cast<int>(m_obstacle_triangles.size());
#pragma omp parallel if (obstacle_count > kParallelThreshold)
  {
    std::vector<std::array<int, 2>> local;
#pragma omp for schedule(dynamic, 256) nowait
    for (int i = 0; i < obstacle_count; ++i) {
      const int t = m_obstacle_triangles[i];
      m_hierarchy.for_each_overlap(m_triangle_boxes[t], [&](int c) {
        local.push_back({m_cloth_triangles[c], t});
      });
    }
#pragma omp critical
    m_triangle_pairs.insert(m_triangle_pairs.end(), local.begin(), local.end());
  }

  const auto has_node = [](const std::array<int, 3>& tri, int k) {
    return tri[0] == k || tri[1] == k || tri[2] == k;
  };
  const long pair_count = static_cast<long>(m_triangle_pairs.size());
#pragma omp parallel if (pair_count > kParallelThreshold)
  {
    std::vector<std::array<int, 2>> pt, ee;
    const auto point_triangle = [&](int t_node, int t) {
      for (int p = m_node_start[t_node]; p < m_node_start[t_node + 1]; ++p) {
        const int k = m_owned_nodes[p];
        if (!has_node(m_triangles[t], k) && m_node_boxes[k].overlaps(m_triangle_boxes[t]))
          pt.push_back({k, t});
      }
    };
#pragma omp for schedule(dynamic, 1024) nowait
    for (long i = 0; i < pair_count; ++i) {
      const auto [t1, t2] = m_triangle_pairs[i];
      point_triangle(t1, t2);
      point_triangle(t2, t1);
      for (int p = m_edge_start[t1]; p < m_edge_start[t1 + 1]; ++p)
        for (int q = m_edge_start[t2]; q < m_edge_start[t2 + 1]; ++q) {
          const int e = m_owned_edges[p], f = m_owned_edges[q];
          const auto &ea = m_edges[e], &eb = m_edges[f];
          if (ea[0] == eb[0] || ea[0] == eb[1] || ea[1] == eb[0] || ea[1] == eb[1]) continue;
          if (m_edge_boxes[e].overlaps(m_edge_boxes[f]))
            ee.push_back({std::min(e, f), std::max(e, f)});
        }
    }
#pragma omp critical
    {
      out.point_triangle.insert(out.point_triangle.end(), pt.begin(), pt.end());
      out.edge_edge.insert(out.edge_edge.end(), ee.begin(), ee.end());
    }
  }
}

}  // namespace shellflow::cloth

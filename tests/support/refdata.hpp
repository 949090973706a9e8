#pragma once
// Loads ../shared/refdata/cases.json: reference cases with exact answers from the heat-transfer
// literature. Tests compare the library against these, never against its own earlier output.

#include <radiosity/geometry/patch_table.hpp>
#include <radiosity/geometry/vec.hpp>

#include <nlohmann/json.hpp>

#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace refdata {

using Polygon = std::vector<radiosity::Vec3>;

/// The whole cases.json document (loaded once).
inline const nlohmann::json& document() {
    static const nlohmann::json doc = [] {
        const std::string path = std::string(RADIOSITY_REFDATA_DIR) + "/cases.json";
        std::ifstream in(path);
        if (!in) throw std::runtime_error("cannot open reference data " + path);
        return nlohmann::json::parse(in);
    }();
    return doc;
}

/// The case of the given name.
inline const nlohmann::json& find_case(const std::string& name) {
    for (const auto& c : document()["cases"])
        if (c["name"] == name) return c;
    throw std::runtime_error("no reference case " + name);
}

/// Names of the cases of one kind ("form_factor" or "solution"), optionally only those with
/// the given expected_shape ("scalar", "matrix", "per_polygon") and real geometry.
inline std::vector<std::string> case_names(const std::string& kind, const std::string& shape = "",
                                           bool need_geometry = true) {
    std::vector<std::string> out;
    for (const auto& c : document()["cases"]) {
        if (c["kind"] != kind) continue;
        if (!shape.empty() && c.value("expected_shape", "") != shape) continue;
        if (need_geometry && c.value("analytic_only", false)) continue;
        out.push_back(c["name"]);
    }
    return out;
}

inline radiosity::Vec3 vec3(const nlohmann::json& a) {
    return {a[0].get<double>(), a[1].get<double>(), a[2].get<double>()};
}

/// The polygons of a case.
inline std::vector<Polygon> polygons(const nlohmann::json& c) {
    std::vector<Polygon> out;
    for (const auto& poly : c["geometry"]) {
        Polygon p;
        for (const auto& v : poly) p.push_back(vec3(v));
        out.push_back(p);
    }
    return out;
}

/// A patch table with one patch per polygon of a case.
inline radiosity::PatchTable table(const nlohmann::json& c) {
    radiosity::PatchTable t;
    for (const auto& p : polygons(c)) t.add(p);
    return t;
}

/// A matrix (list of rows) as nested vectors.
inline std::vector<std::vector<double>> matrix(const nlohmann::json& m) {
    return m.get<std::vector<std::vector<double>>>();
}

}  // namespace refdata

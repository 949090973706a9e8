// One row of F and its checks (form_factor_row.hpp).
#include "form_factor_row.hpp"

#include <algorithm>
#include <cstdio>
#include <cmath>
#include <limits>

namespace radiosity::view {

double row_reciprocity(const radiosity::PatchTable& table, std::size_t i,
                       const std::vector<float>& row, const std::vector<float>& column) {
    double worst = 0.0, scale = 0.0;
    for (std::size_t j = 0; j < row.size(); ++j) {
        const double AiFij = table.area(i) * row[j], AjFji = table.area(j) * column[j];
        worst = std::max(worst, std::abs(AiFij - AjFji));
        scale = std::max(scale, AiFij);
    }
    return scale > 0.0 ? worst / scale : 0.0;
}

FormFactorRow form_factor_row(const Patches& patches, const radiosity::DenseMatrix* F,
                              std::size_t i) {
    const std::size_t n = patches.size();
    FormFactorRow r;
    r.patch = i;
    r.F.resize(n);
    if (F != nullptr)
        std::copy(F->row(i).begin(), F->row(i).end(), r.F.begin());
    else
        patches.row(i, r.F);
    r.self = r.F[i];
    r.smallest = std::numeric_limits<double>::infinity();
    for (float f : r.F) {
        r.sum += f;
        r.largest = std::max(r.largest, double(f));
        if (f > 0.0f) r.smallest = std::min(r.smallest, double(f));
    }
    if (!std::isfinite(r.smallest)) r.smallest = 0.0;
    std::vector<float> column(n);
    if (F != nullptr) {
        for (std::size_t j = 0; j < n; ++j) column[j] = (*F)(j, i);
        r.reciprocity = row_reciprocity(patches.table(), i, r.F, column);
    } else if (patches.has_pairs()) {  // pairs: column i costs one more row's work
        for (std::size_t j = 0; j < n; ++j) column[j] = static_cast<float>(*patches.pair(j, i));
        r.reciprocity = row_reciprocity(patches.table(), i, r.F, column);
    }
    return r;
}

std::string describe_row(const FormFactorRow& r) {
    char line[160];
    std::string out;
    std::snprintf(line, sizeof line, "  F_ii = %.6g\n  row sum = %.6f\n", r.self, r.sum);
    out += line;
    if (r.reciprocity)
        std::snprintf(line, sizeof line, "  reciprocity error = %.6e\n", *r.reciprocity);
    else
        std::snprintf(line, sizeof line, "  reciprocity error = (column not computed)\n");
    return out + line;
}

}  // namespace radiosity::view

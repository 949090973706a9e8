#pragma once
/// @file form_factor_row.hpp  One row of the form-factor matrix, as the viewer shows it for a
/// picked patch: F_ij for every j, the self term F_ii (0 for a flat patch, which cannot see
/// itself), the row sum sum_j F_ij (1 in a closed scene, less where light escapes) and the
/// row's reciprocity error max_j |A_i F_ij - A_j F_ji| / max_j A_i F_ij (0 for an exact F).

#include "patches.hpp"

#include <radiosity/form_factor/matrix.hpp>

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

namespace radiosity::view {

/// Row i of F and what it says about the method.
struct FormFactorRow {
    std::size_t patch = 0;              ///< i
    std::vector<float> F;               ///< F_ij for every patch j
    double self = 0.0;                  ///< F_ii
    double sum = 0.0;                   ///< sum_j F_ij
    double largest = 0.0;               ///< max_j F_ij (the top of the false-colour scale)
    double smallest = 0.0;              ///< min_j F_ij over F_ij > 0
    std::optional<double> reciprocity;  ///< the reciprocity error, once column i is known
};

/// Row i from the assembled matrix if there is one, else from the method; the reciprocity error
/// too when column i is at hand (the matrix, or a method that computes single pairs, at the cost
/// of one more row). Cost: one row (and a column) of the method, O(n) from a matrix.
FormFactorRow form_factor_row(const Patches& patches, const radiosity::DenseMatrix* F,
                              std::size_t i);

/// The reciprocity error of row i against column i (column[j] = F_ji): max_j |A_i F_ij -
/// A_j F_ji| / max_j A_i F_ij, as radiosity::check_matrix measures it over the whole matrix.
double row_reciprocity(const radiosity::PatchTable& table, std::size_t i,
                       const std::vector<float>& row, const std::vector<float>& column);

/// The row's numbers as lines of text for stdout: "F_ii = ...", "row sum = ...",
/// "reciprocity error = ..." (or that it is not known), each line indented by two spaces.
std::string describe_row(const FormFactorRow& row);

}  // namespace radiosity::view

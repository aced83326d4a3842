// The product on every core is the product: random matrices of the sizes the solve and the gather
// use (and one too small to split), against Eigen's own.
#include "radiosity/product.h"

#include <gtest/gtest.h>

using namespace metamer::radiosity;

TEST(Product, EveryCoreGivesEigensProduct) {
    for (const auto& [rows, inner, cols] : {std::tuple{300, 300, 61}, {257, 301, 7}, {40, 30, 3}, {500, 200, 1}}) {
        const Eigen::MatrixXd a = Eigen::MatrixXd::Random(rows, inner), b = Eigen::MatrixXd::Random(inner, cols);
        const Eigen::MatrixXd expected = a * b, got = timesOnEveryCore(a, b);
        ASSERT_EQ(got.rows(), rows);
        ASSERT_EQ(got.cols(), cols);
        EXPECT_LE((got - expected).cwiseAbs().maxCoeff(), 1e-12 * expected.cwiseAbs().maxCoeff()) << rows << "×" << inner << "×" << cols;
    }
}

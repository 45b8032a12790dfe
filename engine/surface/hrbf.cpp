#include "surface/hrbf.h"

#include "base/common.h"
#include "surface/r3_term.h"

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace ink {

using Eigen::Matrix3d;
using Eigen::Vector3d;

Frame Frame::unitDiagonal(const std::vector<Vector3d>& points) {
    Frame frame;
    if (points.empty()) return frame;
    Vector3d lo = points[0], hi = points[0];
    for (const Vector3d& p : points) {
        lo = lo.cwiseMin(p);
        hi = hi.cwiseMax(p);
    }
    frame.center = 0.5 * lo + 0.5 * hi;  // halves first: lo + hi may overflow
    if (!lo.allFinite() || !hi.allFinite()) throw Error("the points have a NaN or infinite coordinate");
    // stableNorm: the squares of a tiny or huge extent would underflow to 0 or overflow to infinity.
    double diagonal = (hi - lo).stableNorm();
    if (diagonal == 0) throw Error("the points span no volume: all positions coincide");
    if (!std::isfinite(diagonal) || !std::isfinite(1.0 / diagonal)) {
        char text[32];
        std::snprintf(text, sizeof text, "%g", diagonal);
        throw Error(std::string("the points' bounding box is too large or too small to normalize (diagonal ") + text +
                    ")");
    }
    frame.scale = 1.0 / diagonal;
    return frame;
}

double Hrbf::f(const Vector3d& x) const {
    double sum = a.dot(x) + b;
    for (size_t j = 0; j < centers.size(); ++j) {
        Vector3d d = x - centers[j];
        double r = d.norm();
        sum += alpha[j] * r * r * r - 3.0 * r * beta[j].dot(d);  // α ψ(d) − ⟨β, ∇ψ(d)⟩
    }
    return sum;
}

double Hrbf::eval(const Vector3d& x, Vector3d& gradient, Matrix3d* hessian) const {
    double sum = a.dot(x) + b;
    Vector3d g = a;
    Matrix3d h = Matrix3d::Zero();
    for (size_t j = 0; j < centers.size(); ++j)
        addR3Node<double>(x, centers[j], alpha[j], beta[j], sum, g, hessian ? &h : nullptr);
    gradient = g;
    if (hessian) *hessian = h;
    return sum;
}

namespace {

// Assembles eq. 5 with the linear term: unknowns [α_1 β_1 … α_m β_m | b a], the rows of eq. 7/8 for each
// point, then eq. 9/10. Both triangles are filled: LAPACK factors the lower one in place and the residual
// is computed from the upper one, which it leaves untouched. Every diagonal entry is zero (ψ, ∇ψ and Hψ
// vanish at r = 0), hence the need for a symmetric *indefinite* factorization.
void assemble(const std::vector<Vector3d>& points, const std::vector<Vector3d>& normals, Eigen::MatrixXd& A,
              Eigen::VectorXd& B) {
    const size_t m = points.size();
    const Eigen::Index n = Eigen::Index(4 * m + 4), poly = Eigen::Index(4 * m);
    A.setZero(n, n);
    B.setZero(n);
    for (size_t i = 0; i < m; ++i) {
        const Eigen::Index row = Eigen::Index(4 * i);
        for (size_t j = 0; j < i; ++j) {
            Vector3d d = points[i] - points[j];
            double r = d.norm();
            if (r == 0.0)
                throw Error("the HRBF system is singular: control points " + std::to_string(j) + " and " +
                            std::to_string(i) + " coincide (merge duplicate points before fitting)");
            Eigen::Matrix4d K;  // block (i, j): [ψ(d) −∇ψ(d)ᵀ; ∇ψ(d) −Hψ(d)]; block (j, i) is its transpose
            K(0, 0) = r * r * r;
            K.block<1, 3>(0, 1) = -3.0 * r * d.transpose();
            K.block<3, 1>(1, 0) = 3.0 * r * d;
            K.block<3, 3>(1, 1) = -(3.0 / r) * (r * r * Matrix3d::Identity() + d * d.transpose());
            const Eigen::Index col = Eigen::Index(4 * j);
            A.block<4, 4>(row, col) = K;
            A.block<4, 4>(col, row) = K.transpose();
        }
        A(row, poly) = A(poly, row) = 1.0;                     // b;  Σ α_j = 0            (eq. 9)
        A.block<1, 3>(row, poly + 1) = points[i].transpose();  // ⟨a, p_i⟩
        A.block<3, 1>(poly + 1, row) = points[i];              // Σ α_j p_j + β_j = 0      (eq. 10)
        A.block<3, 3>(row + 1, poly + 1) = A.block<3, 3>(poly + 1, row + 1) = Matrix3d::Identity();  // a; β_j
        B.segment<3>(row + 1) = normals[i];
    }
}

}  // namespace

// LAPACK (Fortran ABI; the trailing argument is the hidden length of `uplo`). Declared here rather than
// taken from lapacke.h so that any LAPACK will do, reference or OpenBLAS, without another -dev package.
extern "C" void dsysv_(const char* uplo, const int* n, const int* nrhs, double* a, const int* lda, int* ipiv, double* b,
                       const int* ldb, double* work, const int* lwork, int* info, size_t uploLength);

Hrbf fitHrbf(const std::vector<Vector3d>& points, const std::vector<Vector3d>& normals, FitStats* stats) {
    const size_t m = points.size();
    if (m < 2) throw Error("too few distinct points to fit a surface: need at least 2, got " + std::to_string(m));
    if (normals.size() != m)
        throw Error("cannot fit: " + std::to_string(m) + " points but " + std::to_string(normals.size()) + " normals");
    for (size_t i = 0; i < m; ++i) {
        if (!points[i].allFinite() || !normals[i].allFinite())
            throw Error("cannot fit: control point " + std::to_string(i) + " has a NaN or infinite coordinate");
        if (normals[i].squaredNorm() == 0)
            throw Error("cannot fit: control point " + std::to_string(i) + " has a zero normal");
    }
    auto start = std::chrono::steady_clock::now();

    Eigen::MatrixXd A;
    Eigen::VectorXd B;
    assemble(points, normals, A, B);
    const Eigen::VectorXd diagonal = A.diagonal();  // the factorization overwrites it; the residual needs it

    // Bunch–Kaufman LDLᵀ (dsytrf + dsytrs) on the lower triangle, in place: half the flops of LU, and
    // no copy of the matrix. See docs/fitting.md for the measurements behind this choice.
    Eigen::VectorXd x = B;
    const int n = int(A.rows()), one = 1;
    std::vector<int> pivots(static_cast<size_t>(n));
    int info = 0, lwork = -1;
    double bestWork = 0;
    dsysv_("L", &n, &one, A.data(), &n, pivots.data(), x.data(), &n, &bestWork, &lwork, &info, 1);
    lwork = std::max(1, int(bestWork));
    std::vector<double> work(static_cast<size_t>(lwork));
    if (info == 0) dsysv_("L", &n, &one, A.data(), &n, pivots.data(), x.data(), &n, work.data(), &lwork, &info, 1);
    if (info < 0) throw std::logic_error("dsysv: argument " + std::to_string(-info) + " is invalid");
    if (info > 0)
        throw Error("the HRBF system is singular (zero pivot " + std::to_string(info) +
                    "): control points are coincident or degenerate");

    A.diagonal() = diagonal;
    const double residual = (A.selfadjointView<Eigen::Upper>() * x - B).norm() / B.norm();
    // NaN fails this test too. Near-duplicates give tiny pivots rather than zero ones: only this catches them.
    if (!(residual < 1e-6)) {
        char text[32];
        std::snprintf(text, sizeof text, "%.2g", residual);
        throw Error(std::string("the HRBF system is ill-conditioned (relative residual ") + text +
                    "): control points are nearly coincident or degenerate");
    }

    Hrbf model;
    model.centers = points;
    model.normals = normals;
    model.alpha.resize(m);
    model.beta.resize(m);
    for (size_t j = 0; j < m; ++j) {
        model.alpha[j] = x(Eigen::Index(4 * j));
        model.beta[j] = x.segment<3>(Eigen::Index(4 * j + 1));
    }
    model.b = x(Eigen::Index(4 * m));
    model.a = x.segment<3>(Eigen::Index(4 * m + 1));

    if (stats) {
        PhaseTimes phases = std::move(stats->phases);
        *stats = measureFit(model);
        stats->phases = std::move(phases);
        stats->relativeResidual = residual;
        stats->seconds = secondsSince(start);
    }
    return model;
}

FitStats measureFit(const Hrbf& model) {
    FitStats stats;
    stats.controlPoints = model.size();
    for (size_t i = 0; i < model.size(); ++i) {
        Vector3d g;
        double fi = model.eval(model.centers[i], g);
        double gn = g.norm();
        stats.maxDistance = std::max(stats.maxDistance, gn > 0 ? std::abs(fi) / gn : INFINITY);
        if (i < model.normals.size()) {
            const Vector3d& n = model.normals[i];
            double angle = std::atan2(g.cross(n).norm(), g.dot(n));  // accurate near 0, unlike acos
            stats.maxNormalAngleDeg = std::max(stats.maxNormalAngleDeg, angle * 180.0 / M_PI);
        }
    }
    return stats;
}

Curvature principalCurvatures(const Vector3d& gradient, const Matrix3d& hessian) {
    Curvature c;
    double gn = gradient.norm();
    if (!(gn > 0)) return c;
    Vector3d n = gradient / gn;
    Matrix3d P = Matrix3d::Identity() - n * n.transpose();
    Matrix3d S = P * hessian * P / gn;  // shape operator on the tangent plane, symmetric
    Eigen::SelfAdjointEigenSolver<Matrix3d> es(S);
    // One eigenvector is n (eigenvalue 0); the two most tangent ones carry the curvatures.
    int normalIndex = 0;
    for (int k = 1; k < 3; ++k)
        if (std::abs(es.eigenvectors().col(k).dot(n)) > std::abs(es.eigenvectors().col(normalIndex).dot(n)))
            normalIndex = k;
    int i1 = normalIndex == 0 ? 1 : 0, i2 = normalIndex == 2 ? 1 : 2;
    if (es.eigenvalues()(i1) > es.eigenvalues()(i2)) std::swap(i1, i2);
    c.k1 = es.eigenvalues()(i1);
    c.k2 = es.eigenvalues()(i2);
    c.d1 = es.eigenvectors().col(i1).normalized();
    c.d2 = es.eigenvectors().col(i2).normalized();
    return c;
}

}  // namespace ink

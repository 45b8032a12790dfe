#include "hrbf.h"

#include "common.h"

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <Eigen/LU>
#include <algorithm>
#include <chrono>
#include <cmath>

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
    frame.center = 0.5 * (lo + hi);
    double diagonal = (hi - lo).norm();
    if (!(diagonal > 0) || !std::isfinite(diagonal)) throw Error("the points span no volume: all positions coincide");
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
    for (size_t j = 0; j < centers.size(); ++j) {
        Vector3d d = x - centers[j];
        double r = d.norm();
        double db = beta[j].dot(d);
        sum += alpha[j] * r * r * r - 3.0 * r * db;
        if (r == 0.0) continue;  // ∇ψ, Hψ and their derivatives vanish at the centre
        // ∇f_j = α ∇ψ(d) − Hψ(d) β = 3α r d − 3(r β + d ⟨d,β⟩ / r)
        g += 3.0 * alpha[j] * r * d - 3.0 * (r * beta[j] + d * (db / r));
        if (hessian) {
            // α Hψ(d) − ∂(Hψ(d) β)/∂x; the third derivative of ψ contracted with β.
            Matrix3d ddT = d * d.transpose();
            h += 3.0 * alpha[j] * (r * Matrix3d::Identity() + ddT / r);
            h -= (3.0 / r) * (beta[j] * d.transpose() + d * beta[j].transpose() +
                              db * Matrix3d::Identity() - ddT * (db / (r * r)));
        }
    }
    gradient = g;
    if (hessian) *hessian = h;
    return sum;
}

Hrbf fitHrbf(const std::vector<Vector3d>& points, const std::vector<Vector3d>& normals, FitStats* stats) {
    const size_t m = points.size();
    if (m < 2) throw Error("too few distinct points to fit a surface: need at least 2, got " + std::to_string(m));
    auto start = std::chrono::steady_clock::now();

    // Unknowns [α_1 β_1 … α_m β_m | b a]; eq. 7/8 rows per point, eq. 9/10 rows last. Symmetric, indefinite.
    const Eigen::Index n = Eigen::Index(4 * m + 4);
    Eigen::MatrixXd A = Eigen::MatrixXd::Zero(n, n);
    Eigen::VectorXd B = Eigen::VectorXd::Zero(n);
    for (size_t i = 0; i < m; ++i) {
        const Eigen::Index row = Eigen::Index(4 * i);
        for (size_t j = 0; j < m; ++j) {
            const Eigen::Index col = Eigen::Index(4 * j);
            Vector3d d = points[i] - points[j];
            double r = d.norm();
            A(row, col) = r * r * r;                                    //  ψ(d)
            if (r == 0.0) continue;
            A.block<1, 3>(row, col + 1) = -3.0 * r * d.transpose();    // −∇ψ(d)ᵀ
            A.block<3, 1>(row + 1, col) = 3.0 * r * d;                 //  ∇ψ(d)
            A.block<3, 3>(row + 1, col + 1) =
                -(3.0 / r) * (r * r * Matrix3d::Identity() + d * d.transpose());  // −Hψ(d)
        }
        const Eigen::Index poly = Eigen::Index(4 * m);
        A(row, poly) = 1.0;                                            // b
        A.block<1, 3>(row, poly + 1) = points[i].transpose();          // ⟨a, p_i⟩
        A.block<3, 3>(row + 1, poly + 1) = Matrix3d::Identity();      // a
        A(poly, row) = 1.0;                                            // Σ α_j = 0          (eq. 9)
        A.block<3, 1>(poly + 1, row) = points[i];                      // Σ α_j p_j + β_j = 0 (eq. 10)
        A.block<3, 3>(poly + 1, row + 1) = Matrix3d::Identity();
        B.segment<3>(row + 1) = normals[i];
    }

    Eigen::PartialPivLU<Eigen::MatrixXd> lu(A);
    Eigen::VectorXd x = lu.solve(B);
    if (!x.allFinite()) throw Error("the HRBF system is singular: are there duplicate or coplanar-only points?");

    Hrbf model;
    model.centers = points;
    model.alpha.resize(m);
    model.beta.resize(m);
    for (size_t j = 0; j < m; ++j) {
        model.alpha[j] = x(Eigen::Index(4 * j));
        model.beta[j] = x.segment<3>(Eigen::Index(4 * j + 1));
    }
    model.b = x(Eigen::Index(4 * m));
    model.a = x.segment<3>(Eigen::Index(4 * m + 1));

    const double residual = (A * x - B).norm() / B.norm();
    if (!(residual < 1e-6))
        throw Error("the HRBF system is ill-conditioned (relative residual " + std::to_string(residual) +
                    "): control points are nearly coincident or degenerate");
    if (stats) {
        stats->controlPoints = m;
        stats->relativeResidual = residual;
        stats->maxDistance = 0;
        stats->maxNormalAngleDeg = 0;
        for (size_t i = 0; i < m; ++i) {
            Vector3d g;
            double fi = model.eval(points[i], g);
            double gn = g.norm();
            stats->maxDistance = std::max(stats->maxDistance, gn > 0 ? std::abs(fi) / gn : INFINITY);
            double angle = std::atan2(g.cross(normals[i]).norm(), g.dot(normals[i]));  // accurate near 0
            stats->maxNormalAngleDeg = std::max(stats->maxNormalAngleDeg, angle * 180.0 / M_PI);
        }
        stats->seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    }
    return model;
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

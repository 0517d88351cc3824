#include "detail/face_jacobian.h"

namespace vessel::detail {

std::vector<FaceOperator> face_operators(const Mesh& mesh)
{
    std::vector<FaceOperator> ops(mesh.n_faces());
    for (auto f : mesh.faces())
    {
        auto h = f.halfedge();
        FaceOperator& op = ops[f.idx()];
        op.corner = {h.from().idx(), h.to().idx(), h.next().to().idx()};
        const Eigen::Vector3d q0 = to_eigen(mesh.point(h.from()));
        const Eigen::Vector3d e1 = to_eigen(mesh.point(h.to())) - q0;
        const Eigen::Vector3d e2 = to_eigen(mesh.point(h.next().to())) - q0;
        const Eigen::Vector3d ax = e1.normalized();
        const Eigen::Vector3d ay = (e2 - e2.dot(ax) * ax).normalized();
        Eigen::Matrix2d P;  // columns: the two edges in a local orthonormal frame
        P << e1.dot(ax), e2.dot(ax), 0.0, e2.dot(ay);
        const Eigen::Matrix2d Pi = P.inverse();
        op.d0 = {-(Pi(0, 0) + Pi(1, 0)), Pi(0, 0), Pi(1, 0)};
        op.d1 = {-(Pi(0, 1) + Pi(1, 1)), Pi(0, 1), Pi(1, 1)};
        op.area = 0.5 * std::abs(P.determinant());
    }
    return ops;
}

}  // namespace vessel::detail

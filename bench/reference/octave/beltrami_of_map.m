function mu = beltrami_of_map(src, dst, f)
% Beltrami coefficient of the piecewise linear map taking each triangle of
% (src, f) to the triangle of (dst, f), both in R^3: every triangle is laid
% in its own plane with its first edge along the x axis (orientation kept),
% and mu = f_zbar / f_z of the affine map between the two planar triangles.
[s2, s3] = planar(src, f);
[t2, t3] = planar(dst, f);
% Affine map x -> J x with J [s2 s3] = [t2 t3] (first corners at 0).
det_s = s2(:, 1) .* s3(:, 2) - s2(:, 2) .* s3(:, 1);
a = (t2(:, 1) .* s3(:, 2) - t3(:, 1) .* s2(:, 2)) ./ det_s;   % du/dx
b = (t3(:, 1) .* s2(:, 1) - t2(:, 1) .* s3(:, 1)) ./ det_s;   % du/dy
c = (t2(:, 2) .* s3(:, 2) - t3(:, 2) .* s2(:, 2)) ./ det_s;   % dv/dx
d = (t3(:, 2) .* s2(:, 1) - t2(:, 2) .* s3(:, 1)) ./ det_s;   % dv/dy
fz = 0.5 * ((a + d) + 1i * (c - b));
fzbar = 0.5 * ((a - d) + 1i * (c + b));
mu = fzbar ./ fz;
end

function [p2, p3] = planar(v, f)
% Corners 2 and 3 of every face in its own frame (corner 1 at the origin,
% corner 2 on the positive x axis, corner 3 above it).
e1 = v(f(:, 2), :) - v(f(:, 1), :);
e2 = v(f(:, 3), :) - v(f(:, 1), :);
l1 = sqrt(sum(e1 .^ 2, 2));
x = e1 ./ l1;
n = cross(e1, e2, 2);
y = cross(n ./ sqrt(sum(n .^ 2, 2)), x, 2);
p2 = [l1, zeros(size(l1))];
p3 = [sum(e2 .* x, 2), sum(e2 .* y, 2)];
end

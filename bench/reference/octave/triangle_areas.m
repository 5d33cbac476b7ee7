function A = triangle_areas(v, f)
% Area of every face of the mesh (v, f).
n = cross(v(f(:, 2), :) - v(f(:, 1), :), v(f(:, 3), :) - v(f(:, 1), :), 2);
A = 0.5 * sqrt(sum(n .^ 2, 2));
end

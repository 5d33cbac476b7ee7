function F = scatteredInterpolant(x, y, values)
% Stand-in for MATLAB's scatteredInterpolant (which Octave lacks), as the
% authors' ellipsoidal_conformal_map calls it: F = scatteredInterpolant(x, y, v)
% and then F(xq, yq). Linear interpolation on the Delaunay triangulation of
% the sites (x, y), as MATLAB's default 'linear' method. A query outside the
% triangulation (MATLAB extrapolates linearly there) takes the value of its
% nearest site; the authors' map queries its own sites' plane, so this is
% rare. The triangulation is built once, when F is made; the point location
% is Octave's compiled tsearch.
x = x(:); y = y(:); values = values(:);
tri = delaunay(x, y);
F = @(xq, yq) interpolate(tri, x, y, values, xq(:), yq(:));
end

function out = interpolate(tri, x, y, values, xq, yq)
t = tsearch(x, y, tri, xq, yq);
out = nan(size(xq));
inside = ~isnan(t);
c = tri(t(inside), :);
px = xq(inside); py = yq(inside);
x1 = x(c(:, 1)); y1 = y(c(:, 1));
x2 = x(c(:, 2)); y2 = y(c(:, 2));
x3 = x(c(:, 3)); y3 = y(c(:, 3));
d = (y2 - y3) .* (x1 - x3) + (x3 - x2) .* (y1 - y3);
l1 = ((y2 - y3) .* (px - x3) + (x3 - x2) .* (py - y3)) ./ d;
l2 = ((y3 - y1) .* (px - x3) + (x1 - x3) .* (py - y3)) ./ d;
l3 = 1 - l1 - l2;
out(inside) = l1 .* values(c(:, 1)) + l2 .* values(c(:, 2)) + l3 .* values(c(:, 3));
if any(~inside)
  out(~inside) = values(dsearchn([x, y], [xq(~inside), yq(~inside)]));
end
end

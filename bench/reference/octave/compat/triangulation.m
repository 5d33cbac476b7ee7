function tr = triangulation(f, v)
% Stand-in for MATLAB's triangulation class, which Octave lacks. The reference
% code only reads tr.freeBoundary: the boundary edges [a b], each oriented as
% it appears in its one face (a -> b), as MATLAB returns them. A struct with
% that field computed up front serves the same expression.
e = [f(:, [1 2]); f(:, [2 3]); f(:, [3 1])];
n = max(f(:));
key = (e(:, 1) - 1) * n + e(:, 2);
rev = (e(:, 2) - 1) * n + e(:, 1);
free = ~ismember(key, rev);
tr = struct('Points', v, 'ConnectivityList', f, 'freeBoundary', e(free, :));
end

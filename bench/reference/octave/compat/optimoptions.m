function opts = optimoptions(solver, varargin)
% Stand-in for MATLAB's optimoptions (Optimization Toolbox), which Octave lacks.
% Returns a struct holding the solver name and the name/value pairs given;
% the fmincon stand-in beside this file reads MaxIterations from it.
opts = struct('Solver', solver);
for k = 1:2:numel(varargin)
  opts.(varargin{k}) = varargin{k+1};
end
end
